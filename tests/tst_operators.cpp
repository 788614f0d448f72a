// SPH operators with the default kernel (Wendland C2, h = 1.5 dx): lattice errors,
// the errors on jittered lattices (kept from getting worse), and the symmetry of the
// Laplacian that the pressure Poisson solve relies on.
#include "kernels/wendland_c2.hpp"
#include "tests/operator_errors.hpp"
#include "tests/test_space.hpp"

#include <catch2/catch.hpp>

using namespace dvisph;
using testing::operator_errors;

namespace {
constexpr Real default_h_over_dx = 1.5;  // the scene default (src/schema.cpp)

void report(const char* what, const testing::OperatorErrors& e) {
  WARN(what << ": interior " << e.interior << " | gradient mean " << e.gradient.mean << " p95 "
            << e.gradient.p95 << " | divergence mean " << e.divergence.mean << " p95 "
            << e.divergence.p95 << " | laplacian mean " << e.laplacian.mean << " p95 "
            << e.laplacian.p95);
}
}  // namespace

TEST_CASE("operators on a regular lattice", "[operators]") {
  const auto e2 = operator_errors<TestSpace, WendlandC2<2>>(default_h_over_dx, 0);
  const auto e3 = operator_errors<TestSpace, WendlandC2<3>>(default_h_over_dx, 0);
  report("2D lattice", e2);
  report("3D lattice", e3);
  for (const auto& e : {e2, e3}) {
    CHECK(e.interior > 200);
    CHECK(e.gradient.max < 0.02);
    CHECK(e.divergence.max < 0.02);
    CHECK(e.laplacian.max < 0.03);
  }
}

// Bounds: the figures measured when this test was written (docs in the closing note of
// the foundation issue), plus 5 %: a change that makes the operators worse fails here.
TEST_CASE("operators on jittered lattices do not get worse", "[operators]") {
  struct Case {
    int dim;
    Real jitter;
    Real grad_mean, grad_p95, div_mean, div_p95, lap_mean, lap_p95;
  };
  const Case cases[] = {
      //  gradient      divergence        Laplacian   (mean, p95 of relative error)
      {2, 0.05, 0.280, 0.789, 0.0073, 0.0175, 0.313, 0.804},
      {2, 0.10, 0.559, 1.567, 0.0143, 0.0344, 0.623, 1.638},
      {3, 0.05, 0.191, 0.460, 0.0044, 0.0108, 0.111, 0.289},
      {3, 0.10, 0.380, 0.923, 0.0087, 0.0218, 0.220, 0.585},
  };
  for (const auto& c : cases) {
    const auto e = c.dim == 2
                       ? operator_errors<TestSpace, WendlandC2<2>>(default_h_over_dx, c.jitter)
                       : operator_errors<TestSpace, WendlandC2<3>>(default_h_over_dx, c.jitter);
    report(c.dim == 2 ? (c.jitter < 0.07 ? "2D jitter 0.05" : "2D jitter 0.10")
                      : (c.jitter < 0.07 ? "3D jitter 0.05" : "3D jitter 0.10"),
           e);
    const Real slack = 1.05;
    CHECK(e.gradient.mean <= slack * c.grad_mean);
    CHECK(e.gradient.p95 <= slack * c.grad_p95);
    CHECK(e.divergence.mean <= slack * c.div_mean);
    CHECK(e.divergence.p95 <= slack * c.div_p95);
    CHECK(e.laplacian.mean <= slack * c.lap_mean);
    CHECK(e.laplacian.p95 <= slack * c.lap_p95);
  }
}

TEST_CASE("the Morris Laplacian is symmetric on disordered particles", "[operators]") {
  using Mem = TestSpace::memory_space;
  constexpr int D = 2;
  const Real dx = 0.01;
  const WendlandC2<D> kernel(default_h_over_dx * dx);
  const auto pts = lattice<D>(Vec<D>{{0, 0}}, Vec<D>{{0.3, 0.2}}, dx, 0.1 * dx, 5);
  const int n = static_cast<int>(pts.size());
  Kokkos::View<Real* [D], Mem> x("x", n);
  copy_points<D>(pts, x);
  Kokkos::View<Real*, Mem> m("m", n), rho("rho", n), u("u", n), w("w", n), Lu("Lu", n), Lw("Lw", n);
  Kokkos::deep_copy(m, 1000 * dx * dx);
  Kokkos::deep_copy(rho, 1000.0);
  Kokkos::parallel_for(
      Kokkos::RangePolicy<TestSpace>(0, n), KOKKOS_LAMBDA(int i) {
        u(i) = math::sin(37.0 * x(i, 0)) + x(i, 1);
        w(i) = math::cos(23.0 * x(i, 1)) * x(i, 0);
      });
  CellList<D, TestSpace> cells(Grid<D>(Vec<D>{{-dx, -dx}}, Vec<D>{{0.31, 0.21}}, kernel.radius()));
  cells.build(x, n);
  const CellSweep<D, TestSpace> sweep(cells, x, kernel.radius());
  laplacian<D>(sweep, kernel, x, m, rho, u, Lu, n);
  laplacian<D>(sweep, kernel, x, m, rho, w, Lw, n);
  Real wLu = 0, uLw = 0, scale = 0;
  Kokkos::parallel_reduce(
      Kokkos::RangePolicy<TestSpace>(0, n),
      KOKKOS_LAMBDA(int i, Real& s) { s += w(i) * Lu(i); }, wLu);
  Kokkos::parallel_reduce(
      Kokkos::RangePolicy<TestSpace>(0, n),
      KOKKOS_LAMBDA(int i, Real& s) { s += u(i) * Lw(i); }, uLw);
  Kokkos::parallel_reduce(
      Kokkos::RangePolicy<TestSpace>(0, n),
      KOKKOS_LAMBDA(int i, Real& s) { s += math::abs(w(i) * Lu(i)); }, scale);
  CHECK(std::abs(wLu - uLw) < 1e-12 * scale);
}
