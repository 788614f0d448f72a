// Serial and OpenMP compute the same operators on disordered particles to 1e-12.
#include "kernels/cubic_spline.hpp"
#include "tests/operator_errors.hpp"

#include <catch2/catch.hpp>

using namespace dvisph;

TEMPLATE_TEST_CASE("Serial and OpenMP agree on the SPH operators", "[cross_backend]",
                   CubicSpline<2>, CubicSpline<3>) {
  std::vector<Real> serial, openmp;
  testing::operator_errors<Kokkos::Serial, TestType>(1.3, 0.1, &serial);
  testing::operator_errors<Kokkos::OpenMP, TestType>(1.3, 0.1, &openmp);
  REQUIRE(serial.size() == openmp.size());
  Real worst = 0, scale = 0;
  for (std::size_t i = 0; i < serial.size(); ++i) {
    worst = std::max(worst, std::abs(serial[i] - openmp[i]));
    scale = std::max(scale, std::abs(serial[i]));
  }
  WARN("max |Serial - OpenMP| / max |value| = " << worst / scale);
  CHECK(worst <= 1e-12 * scale);
}
