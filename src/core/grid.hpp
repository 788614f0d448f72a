#pragma once
// A uniform grid of cubic cells over a box: maps positions to cells. Shared by the
// cell list (binning) and every neighbour sweep that reads it. Along a periodic axis
// the cells tile the box exactly (the last one absorbs the remainder, so no cell is
// smaller than the cell size) and a neighbourhood of cells wraps around.
#include "src/core/periodic.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dvisph {

template <int D>
struct Grid {
  Real lo[D];
  Real inv_cell;
  Real cell;
  int ncell[D];
  Periodic<D> periodic;

  Grid() = default;
  // periodic_axes: bit k set when axis k wraps over [box_lo[k], box_hi[k])
  Grid(const Vec<D>& box_lo, const Vec<D>& box_hi, Real cell_size, unsigned periodic_axes = 0)
      : cell(cell_size), periodic(box_lo, box_hi, periodic_axes) {
    if (!(cell_size > 0)) throw std::invalid_argument("Grid: cell size must be > 0");
    inv_cell = 1.0 / cell_size;
    long total = 1;
    for (int k = 0; k < D; ++k) {
      if (!(box_hi[k] > box_lo[k]))
        throw std::invalid_argument("Grid: empty box along axis " + std::to_string(k));
      lo[k] = box_lo[k];
      const Real cells = (box_hi[k] - box_lo[k]) * inv_cell;
      ncell[k] = std::max(1, static_cast<int>(periodic.wraps(k) ? std::floor(cells + 1e-9) : std::ceil(cells)));
      total *= ncell[k];
    }
    if (total > (1L << 30)) throw std::invalid_argument("Grid: more than 2^30 cells");
  }

  int size() const {
    int s = 1;
    for (int k = 0; k < D; ++k) s *= ncell[k];
    return s;
  }

  // Integer cell coordinate along axis k, not clamped (may lie outside the grid).
  KOKKOS_INLINE_FUNCTION int coord(Real xk, int k) const {
    return static_cast<int>(math::floor((xk - lo[k]) * inv_cell));
  }
  KOKKOS_INLINE_FUNCTION int clamp(int c, int k) const {
    return c < 0 ? 0 : (c >= ncell[k] ? ncell[k] - 1 : c);
  }
  KOKKOS_INLINE_FUNCTION int wrap(int c, int k) const {
    return c < 0 ? c + ncell[k] : (c >= ncell[k] ? c - ncell[k] : c);
  }
  // Cells on each side that cover a search radius.
  int reach(Real radius) const { return static_cast<int>(std::ceil(radius / cell - 1e-12)); }
  // Whether `reach` cells on each side of a cell stay distinct cells along every periodic
  // axis (a neighbourhood that wrapped onto itself would visit particles twice).
  bool reach_fits(int reach) const {
    for (int k = 0; k < D; ++k)
      if (periodic.wraps(k) && ncell[k] < 2 * reach + 1) return false;
    return true;
  }
  // f(first, last) for each row of cells (flat indices first..last, consecutive along
  // axis 0) in the block within `reach` cells of the cell coordinates c (unclamped),
  // clipped to the grid, or wrapped along periodic axes (reach_fits(reach)); nothing
  // when the block misses the grid. The one walk over a neighbourhood of cells, for
  // sweeps and neighbourhood tests.
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each_row(const int (&c)[D], int reach, F&& f) const {
    int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (int k = 0; k < D; ++k) {
      if (periodic.wraps(k)) {
        const int ck = clamp(c[k], k);
        lo[k] = ck - reach;
        hi[k] = ck + reach;
        continue;
      }
      if (c[k] + reach < 0 || c[k] - reach >= ncell[k]) return;
      lo[k] = clamp(c[k] - reach, k);
      hi[k] = clamp(c[k] + reach, k);
    }
    const int nx = ncell[0];
    const int ny = D > 1 ? ncell[1] : 1;
    for (int cz = lo[2]; cz <= hi[2]; ++cz)
      for (int cy = lo[1]; cy <= hi[1]; ++cy) {
        const int wz = D > 2 ? wrap(cz, D - 1) : cz, wy = D > 1 ? wrap(cy, D - 1 > 0 ? 1 : 0) : cy;
        const int row = (wz * ny + wy) * nx;
        const int first = wrap(lo[0], 0), last = wrap(hi[0], 0);
        if (first <= last) {
          f(row + first, row + last);
        } else {  // a row across the periodic seam of axis 0: two runs
          f(row + first, row + nx - 1);
          f(row, row + last);
        }
      }
  }

  // Flat index of the cell holding x; positions outside the box go to the nearest cell.
  template <class X>
  KOKKOS_INLINE_FUNCTION int cell_of(const X& x) const {
    int index = 0;
    for (int k = D - 1; k >= 0; --k) index = index * ncell[k] + clamp(coord(x[k], k), k);
    return index;
  }
};

}  // namespace dvisph
