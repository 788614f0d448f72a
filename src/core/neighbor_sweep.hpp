#pragma once
// The one neighbour-loop primitive. A sweep is a small device-copyable object whose
// for_each(i, xi, f) calls f(j, xij, r) for every particle j of a target set with
// |xi - xj| < radius, xij = xi - xj. The query point may belong to another set
// (fluid-solid with a different radius): `i` is only used by stored lists.
// Self pairs (j == i within one set) are visited; kernels give them zero gradient.
#include "src/core/cell_list.hpp"

#include <cmath>
#include <stdexcept>

namespace dvisph {

// xij = xi - x_j at its nearest image along periodic axes; returns |xij|^2. The pair
// vector every sweep computes for its candidates.
template <int D, class XView>
KOKKOS_INLINE_FUNCTION Real pair_vector(const XView& x, int j, const Vec<D>& xi,
                                        const Periodic<D>& periodic, Vec<D>& xij) {
  for (int k = 0; k < D; ++k) xij[k] = xi[k] - x(j, k);
  periodic.nearest_image(xij);
  Real r2 = 0;
  for (int k = 0; k < D; ++k) r2 += xij[k] * xij[k];
  return r2;
}

// Calls f(j, xi - x_j, |xi - x_j|) when candidate j lies within sqrt(radius2) of xi
// (at its nearest image along periodic axes): the distance test every sweep applies to
// its candidates.
template <int D, class XView, class F>
KOKKOS_INLINE_FUNCTION void visit_within(const XView& x, int j, const Vec<D>& xi, Real radius2,
                                         const Periodic<D>& periodic, F&& f) {
  Vec<D> xij;
  const Real r2 = pair_vector<D>(x, j, xi, periodic, xij);
  if (r2 < radius2) f(j, xij, math::sqrt(r2));
}

template <int D, class Space>
struct CellSweep {
  using execution_space = Space;
  using memory_space = typename Space::memory_space;
  Grid<D> grid;
  Kokkos::View<const int*, memory_space> offsets, particles;
  Kokkos::View<const Real* [D], memory_space> x;  // positions of the target set
  Real radius2;
  int reach;  // cells to scan on each side

  CellSweep() = default;
  template <class XView>
  CellSweep(const CellList<D, Space>& cells, const XView& target_x, Real radius)
      : grid(cells.grid()),
        offsets(cells.offsets()),
        particles(cells.permutation()),
        x(target_x),
        radius2(radius * radius),
        reach(cells.grid().reach(radius)) {
    if (!grid.reach_fits(reach))
      throw std::invalid_argument(
          "CellSweep: a periodic axis is shorter than 2 search radii plus a cell; its pairs "
          "would be counted twice");
  }

  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each(int /*i*/, const Vec<D>& xi, F&& f) const {
    for_each_candidate(xi, [&](int j) { visit_within(x, j, xi, radius2, grid.periodic, f); });
  }

  // The targets within the radius of xi, in for_each's order, written to out(first),
  // out(first + 1), ... while below `spare`; those beyond go to out(spare), a scratch
  // slot. Returns how many there are. No branch on the distance test (the store is
  // unconditional, the index advances by the test), so the loop over a row of cells
  // does not stall on it: the stored list's build (neighbor_list.hpp).
  template <class Out>
  KOKKOS_INLINE_FUNCTION int collect(const Vec<D>& xi, const Out& out, int first, int spare) const {
    return within<true>(xi, out, first, spare);
  }
  // How many targets lie within the radius of xi (collect without the stores).
  KOKKOS_INLINE_FUNCTION int count(const Vec<D>& xi) const {
    return within<false>(xi, particles, 0, 0);
  }

  // g(j) for every particle j in the cells within reach of xi's cell, in cell order.
  template <class G>
  KOKKOS_INLINE_FUNCTION void for_each_candidate(const Vec<D>& xi, G&& g) const {
    int c[D];
    for (int k = 0; k < D; ++k) c[k] = grid.coord(xi[k], k);
    grid.for_each_row(c, reach, [&](int first, int last) {
      // the cells of a row are contiguous in the permutation
      const int end = offsets(last + 1);
      for (int a = offsets(first); a < end; ++a) g(particles(a));
    });
  }

  template <bool Store, class Out>
  KOKKOS_INLINE_FUNCTION int within(const Vec<D>& xi, const Out& out, int first, int spare) const {
    int a = first;
    for_each_candidate(xi, [&](int j) {
      Vec<D> xij;
      const Real r2 = pair_vector<D>(x, j, xi, grid.periodic, xij);
      if constexpr (Store) out(a < spare ? a : spare) = j;
      a += r2 < radius2;
    });
    return a - first;
  }
};

}  // namespace dvisph
