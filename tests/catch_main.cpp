// Catch2 main that brings Kokkos up once for all test cases.
#define CATCH_CONFIG_RUNNER
#include <Kokkos_Core.hpp>
#include <catch2/catch.hpp>

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos;
  return Catch::Session().run(argc, argv);
}
