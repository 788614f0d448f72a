// Serial and OpenMP compute the same operators on disordered particles, and the same
// DEM collision, to 1e-12.
#include "kernels/wendland_c2.hpp"
#include "tests/coupled_scenes.hpp"
#include "tests/dem_scenes.hpp"
#include "tests/operator_errors.hpp"

#include <catch2/catch.hpp>

using namespace dvisph;

TEMPLATE_TEST_CASE("Serial and OpenMP agree on the SPH operators", "[cross_backend]",
                   WendlandC2<2>, WendlandC2<3>) {
  std::vector<Real> serial, openmp;
  testing::operator_errors<Kokkos::Serial, TestType>(1.5, 0.1, &serial);
  testing::operator_errors<Kokkos::OpenMP, TestType>(1.5, 0.1, &openmp);
  REQUIRE(serial.size() == openmp.size());
  Real worst = 0, scale = 0;
  for (std::size_t i = 0; i < serial.size(); ++i) {
    worst = std::max(worst, std::abs(serial[i] - openmp[i]));
    scale = std::max(scale, std::abs(serial[i]));
  }
  WARN("max |Serial - OpenMP| / max |value| = " << worst / scale);
  CHECK(worst <= 1e-12 * scale);
}

TEST_CASE("Serial and OpenMP agree on a DEM two-bead collision", "[cross_backend][dem]") {
  const auto serial = testing::two_bead_collision<Kokkos::Serial>();
  const auto openmp = testing::two_bead_collision<Kokkos::OpenMP>();
  Real worst = 0;
  for (std::size_t i = 0; i < serial.size(); ++i)
    for (std::size_t c = 0; c < serial[i].size(); ++c)
      worst = std::max(
          worst, std::abs(serial[i][c] - openmp[i][c]) / std::max(std::abs(serial[i][c]), 1e-300));
  WARN("DEM two-bead collision: max relative |Serial - OpenMP| = " << worst);
  CHECK(worst <= 1e-12);
}

TEST_CASE("Serial and OpenMP agree on water and beads coupled", "[cross_backend][coupling]") {
  const auto serial = testing::coupled_blob_state<Kokkos::Serial>(5);
  const auto openmp = testing::coupled_blob_state<Kokkos::OpenMP>(5);
  REQUIRE(serial.size() == openmp.size());
  Real worst = 0;
  for (std::size_t i = 0; i < serial.size(); ++i)
    worst = std::max(worst, std::abs(serial[i] - openmp[i]) / std::max(std::abs(serial[i]), 1e-300));
  WARN("coupled ball of water and beads, 5 steps: max relative |Serial - OpenMP| = " << worst);
  CHECK(worst <= 1e-12);
}
