// Kernel functions: partition of unity and zero gradient sum on fine lattices, and the
// analytic gradient against a finite difference of W.
#include "kernels/cubic_spline.hpp"
#include "kernels/wendland_c2.hpp"
#include "src/core/lattice.hpp"
#include "tests/test_space.hpp"

#include <catch2/catch.hpp>

using namespace dvisph;

// Sums over a lattice of spacing dx = h/10, at a lattice node (where SPH evaluates them)
// and, reported only, at a point off the nodes.
TEMPLATE_TEST_CASE("kernel sums on a fine lattice", "[kernels]", CubicSpline<2>, CubicSpline<3>,
                   WendlandC2<2>, WendlandC2<3>) {
  constexpr int D = TestType::dim;
  const Real dx = 0.01, h = 10 * dx;
  const TestType kernel(h);
  Vec<D> lo, hi;
  for (int k = 0; k < D; ++k) {
    lo[k] = 0;
    hi[k] = 6 * h;
  }
  const auto pts = lattice<D>(lo, hi, dx);
  Kokkos::View<Real* [D], typename TestSpace::memory_space> x("x", pts.size());
  copy_points<D>(pts, x);
  const Real volume = std::pow(dx, D);

  for (const Real offset : {0.0, 0.37}) {
    Vec<D> x0;
    for (int k = 0; k < D; ++k) x0[k] = 3 * h + 0.5 * dx + offset * dx * (k + 1);
    Real sum_w = 0;
    Kokkos::parallel_reduce(
        Kokkos::RangePolicy<TestSpace>(0, pts.size()),
        KOKKOS_LAMBDA(int j, Real& s) {
          Vec<D> xij = x0 - row<D>(x, j);
          s += kernel.W(math::sqrt(dot(xij, xij))) * volume;
        },
        sum_w);
    Real sum_g = 0;  // largest component of sum grad W V, made dimensionless by h
    for (int k = 0; k < D; ++k) {
      Real g = 0;
      Kokkos::parallel_reduce(
          Kokkos::RangePolicy<TestSpace>(0, pts.size()),
          KOKKOS_LAMBDA(int j, Real& s) {
            Vec<D> xij = x0 - row<D>(x, j);
            s += kernel.grad(xij, math::sqrt(dot(xij, xij)))[k] * volume;
          },
          g);
      sum_g = std::max(sum_g, std::abs(g) * h);
    }
    WARN(TestType::name << " " << D << "D h/dx=10, offset " << offset << " dx: |sum W V - 1| = "
                        << std::abs(sum_w - 1) << ", |sum grad W V| h = " << sum_g);
    if (offset == 0) {
      CHECK(std::abs(sum_w - 1) < 1e-6);
      CHECK(sum_g < 1e-6);
    }
  }
}

TEMPLATE_TEST_CASE("analytic gradient equals a finite difference of W", "[kernels]",
                   CubicSpline<2>, CubicSpline<3>, WendlandC2<2>, WendlandC2<3>) {
  constexpr int D = TestType::dim;
  const Real h = 0.013;
  const TestType kernel(h);
  const Real eps = 1e-7 * h;
  Real worst = 0;
  for (Real q = 0.05; q < 2.0; q += 0.0371) {
    Vec<D> x;
    for (int k = 0; k < D; ++k) x[k] = q * h * (k == 0 ? 0.8 : 0.6 / std::sqrt(D - 1.0));
    const Real r = std::sqrt(dot(x, x));
    const Vec<D> g = kernel.grad(x, r);
    for (int k = 0; k < D; ++k) {
      Vec<D> xp = x, xm = x;
      xp[k] += eps;
      xm[k] -= eps;
      const Real fd = (kernel.W(std::sqrt(dot(xp, xp))) - kernel.W(std::sqrt(dot(xm, xm)))) / (2 * eps);
      worst = std::max(worst, std::abs(fd - g[k]) * h / kernel.W(0));  // relative to W(0)/h
    }
  }
  CHECK(worst < 1e-6);
  CHECK(kernel.W(2.000001 * h) == 0);
  CHECK(kernel.dW_over_r(2.000001 * h) == 0);
}
