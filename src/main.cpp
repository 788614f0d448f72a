#include "src/backend.hpp"

#include <Kokkos_Core.hpp>
#include <fmt/core.h>

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  const auto info = dvisph::backend_info();
  fmt::print("dvisph on {} ({} threads), Kokkos {}\n", info.backend, info.concurrency,
             info.kokkos_version);
  return 0;
}
