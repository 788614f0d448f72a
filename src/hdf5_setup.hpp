#pragma once
// What every HDF5 use in dvisph does first (snapshots, checkpoints), so that a program
// embedding the library gets it too, not only `dvisph`'s main.

namespace dvisph {

// Once: no HDF5 exit handler (HDF5 1.10 crashes in it once a file has failed to close,
// e.g. on a full disk; the writers close their files themselves). Every time: no error
// printing from HDF5 (the writers report errors naming the file).
void prepare_hdf5();

}  // namespace dvisph
