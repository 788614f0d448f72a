#include "src/backend.hpp"

#include <Kokkos_Core.hpp>

namespace dvisph {

BackendInfo backend_info() {
  using Space = Kokkos::DefaultExecutionSpace;
  const int v = KOKKOS_VERSION;
  return {Space::name(), Space().concurrency(),
          std::to_string(v / 10000) + "." + std::to_string(v / 100 % 100) + "." +
              std::to_string(v % 100)};
}

}  // namespace dvisph
