#pragma once
// What this build runs on: backend name, threads, Kokkos version (for summaries and
// benchmark records).
#include <string>

namespace dvisph {

struct BackendInfo {
  std::string backend;  // name of the default execution space, e.g. "OpenMP"
  int concurrency;      // threads (CPU) or concurrent threads (GPU)
  std::string kokkos_version;
};

BackendInfo backend_info();

}  // namespace dvisph
