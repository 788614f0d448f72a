#include "src/hdf5_setup.hpp"

#include <hdf5.h>

namespace dvisph {

void prepare_hdf5() {
  // H5dont_atexit must come before the library initialises, i.e. before any other call
  static const bool no_exit_handler = (H5dont_atexit(), true);
  (void)no_exit_handler;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

}  // namespace dvisph
