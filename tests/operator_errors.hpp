#pragma once
// Pointwise errors of the SPH operators on a (jittered) lattice, at interior particles
// (full kernel support): gradient of a linear field, divergence of a linear vector
// field, Morris Laplacian of a quadratic field. Shared by tests and the kernel study.
#include "kernels/divergence.hpp"
#include "kernels/gradient.hpp"
#include "kernels/laplacian.hpp"
#include "src/core/cell_list.hpp"
#include "src/core/lattice.hpp"
#include "src/core/neighbor_sweep.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

namespace dvisph::testing {

struct ErrorStats {
  Real mean = 0, p95 = 0, max = 0;
  static ErrorStats of(std::vector<Real> e) {
    ErrorStats s;
    std::sort(e.begin(), e.end());
    s.mean = std::accumulate(e.begin(), e.end(), 0.0) / e.size();
    s.p95 = e[static_cast<std::size_t>(0.95 * (e.size() - 1))];
    s.max = e.back();
    return s;
  }
};

struct OperatorErrors {
  ErrorStats gradient, divergence, laplacian;
  int interior = 0;
};

// Also returns the raw operator outputs, for cross-backend comparison.
template <class Space, class Kernel>
OperatorErrors operator_errors(Real h_over_dx, Real jitter_over_dx,
                               std::vector<Real>* raw = nullptr) {
  constexpr int D = Kernel::dim;
  using Mem = typename Space::memory_space;
  const Real dx = 1.0 / 32, h = h_over_dx * dx, rho0 = 1000;
  const Kernel kernel(h);
  const int cells_per_side = D == 2 ? 32 : 20;
  Vec<D> lo, hi;
  for (int k = 0; k < D; ++k) {
    lo[k] = 0;
    hi[k] = cells_per_side * dx;
  }
  const auto pts = lattice<D>(lo, hi, dx, jitter_over_dx * dx, 3);
  const int n = static_cast<int>(pts.size());
  Kokkos::View<Real* [D], Mem> x("x", n), v("v", n), grad("grad", n);
  Kokkos::View<Real*, Mem> m("m", n), rho("rho", n), f("f", n), q("q", n), div("div", n),
      lap("lap", n);
  copy_points<D>(pts, x);
  const Real mass = rho0 * std::pow(dx, D);
  Kokkos::deep_copy(m, mass);
  Kokkos::deep_copy(rho, rho0);

  const Real a[3] = {1.0, -0.7, 0.4};                                       // grad f
  const Real A[3][3] = {{1.0, 0.3, 0.2}, {-0.5, 0.8, 0.1}, {0.2, -0.4, 0.6}};  // v = A x
  const Real b[3] = {1.0, 0.5, 0.25};                                       // q = sum b x^2
  Real trace = 0, lap_exact = 0;
  for (int k = 0; k < D; ++k) {
    trace += A[k][k];
    lap_exact += 2 * b[k];
  }
  Kokkos::parallel_for(
      Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        Real fi = 0, qi = 0;
        for (int k = 0; k < D; ++k) {
          fi += a[k] * x(i, k);
          qi += b[k] * x(i, k) * x(i, k);
          Real vk = 0;
          for (int l = 0; l < D; ++l) vk += A[k][l] * x(i, l);
          v(i, k) = vk;
        }
        f(i) = fi;
        q(i) = qi;
      });

  Vec<D> glo = lo, ghi = hi;
  for (int k = 0; k < D; ++k) glo[k] -= dx, ghi[k] += dx;
  CellList<D, Space> cells(Grid<D>(glo, ghi, kernel.radius()));
  cells.build(x, n);
  const CellSweep<D, Space> sweep(cells, x, kernel.radius());
  symmetric_gradient<D>(sweep, kernel, x, m, rho, f, grad, n);
  divergence<D>(sweep, kernel, x, m, rho, v, div, n);
  laplacian<D>(sweep, kernel, x, m, rho, q, lap, n);

  auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x);
  auto hg = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), grad);
  auto hd = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), div);
  auto hl = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), lap);
  Real norm_a = 0;
  for (int k = 0; k < D; ++k) norm_a += a[k] * a[k];
  norm_a = std::sqrt(norm_a);
  std::vector<Real> eg, ed, el;
  const Real margin = kernel.radius() + jitter_over_dx * dx;
  for (int i = 0; i < n; ++i) {
    bool interior = true;
    for (int k = 0; k < D; ++k)
      interior = interior && hx(i, k) > lo[k] + margin && hx(i, k) < hi[k] - margin;
    if (raw) {
      for (int k = 0; k < D; ++k) raw->push_back(hg(i, k));
      raw->push_back(hd(i));
      raw->push_back(hl(i));
    }
    if (!interior) continue;
    Real e2 = 0;
    for (int k = 0; k < D; ++k) e2 += (hg(i, k) - a[k]) * (hg(i, k) - a[k]);
    eg.push_back(std::sqrt(e2) / norm_a);
    ed.push_back(std::abs(hd(i) - trace) / std::abs(trace));
    el.push_back(std::abs(hl(i) - lap_exact) / lap_exact);
  }
  OperatorErrors out;
  out.interior = static_cast<int>(eg.size());
  out.gradient = ErrorStats::of(eg);
  out.divergence = ErrorStats::of(ed);
  out.laplacian = ErrorStats::of(el);
  return out;
}

}  // namespace dvisph::testing
