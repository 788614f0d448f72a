#pragma once
// The cells of the neighbour grid that hold water, and which particles lie within a
// kernel radius's worth of cells of them. A wall particle farther from the water than
// the kernel radius has no part in a step (role excluded), and in a tank such particles
// are most of the walls (3D dam break, dx = 3 mm: 46 000 wall particles for 8 400 fluid
// ones); they get no neighbour list. Every particle with a fluid neighbour is near a wet
// cell.
#include "src/core/cell_list.hpp"

namespace dvisph {

template <int D, class Space>
class WetCells {
 public:
  using memory_space = typename Space::memory_space;

  // Whether particle i is water or has a wet cell among its own and the `reach` cells on
  // each side (flags of the cells, dilated from the wet ones: one read per particle).
  template <class X, class KindV>
  struct Near {
    Grid<D> grid;
    Kokkos::View<const char*, memory_space> near;
    X x;
    KindV kind;
    KOKKOS_INLINE_FUNCTION bool operator()(int i) const {
      if (kind(i) == Kind::fluid) return true;
      Real xi[D];
      for (int k = 0; k < D; ++k) xi[k] = x(i, k);
      return near(grid.cell_of(xi)) != 0;
    }
  };

  // Counts the fluid particles among the first n in each cell; the test it returns finds
  // the particles with a wet cell within `radius`'s cells.
  template <class X, class KindV>
  Near<X, KindV> mark(const Grid<D>& grid, Real radius, const X& x, const KindV& kind, int n) {
    if (static_cast<int>(wet_.extent(0)) != grid.size()) {
      wet_ = Kokkos::View<char*, memory_space>("dvisph::wet_cells", grid.size());
      near_ = Kokkos::View<char*, memory_space>("dvisph::wet_cells::near", grid.size());
      wide_ = Kokkos::View<char*, memory_space>("dvisph::wet_cells::wide", grid.size());
      pass_ = Kokkos::View<char*, memory_space>("dvisph::wet_cells::pass", grid.size());
    }
    auto wet = wet_;
    Kokkos::deep_copy(Space(), wet, 0);
    Kokkos::parallel_for(
        "dvisph::wet_cells::mark", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          if (kind(i) != Kind::fluid) return;
          Real xi[D];
          for (int k = 0; k < D; ++k) xi[k] = x(i, k);
          wet(grid.cell_of(xi)) = 1;  // every writer writes the same value
        });
    grid_ = grid;
    reach_ = grid.reach(radius);
    dilate(near_, reach_);
    return {grid, near_, x, kind};
  }

  // The same test `margin` cells wider (the particles the water may reach soon), for the
  // x and kind of the last mark.
  template <class X, class KindV>
  Near<X, KindV> wider(const Near<X, KindV>& near, int margin) {
    dilate(wide_, reach_ + margin);
    return {near.grid, wide_, near.x, near.kind};
  }

  std::size_t bytes() const { return view_bytes(wet_, near_, wide_, pass_); }

  // out = the wet flags dilated by `reach` cells along every axis, one axis at a time
  // (a box is the product of its sides), wrapping on periodic axes: along each line of
  // cells a window of 2 reach + 1 cells slides, counting the flagged ones in it. Public
  // for CUDA.
  void dilate(const Kokkos::View<char*, memory_space>& out, int reach) {
    const Grid<D> grid = grid_;
    Kokkos::View<char*, memory_space> from = wet_;
    int stride = 1;
    for (int k = 0; k < D; ++k) {
      // the last pass writes `out`; the passes alternate between out and pass_
      const auto to = (D - 1 - k) % 2 == 0 ? out : pass_;
      const int nk = grid.ncell[k], s = stride;
      const bool wraps = grid.periodic.wraps(k);
      const auto src = from;
      Kokkos::parallel_for(
          "dvisph::wet_cells::dilate", Kokkos::RangePolicy<Space>(0, grid.size() / nk), KOKKOS_LAMBDA(int line) {
            const int base = (line / s) * s * nk + line % s;
            // the cell at c along the line, c in [-nk, 2 nk) on a periodic axis
            auto at = [&](int c) -> int {
              if (wraps) c = c < 0 ? c + nk : (c >= nk ? c - nk : c);
              else if (c < 0 || c >= nk) return 0;
              return src(base + c * s);
            };
            if (wraps && 2 * reach + 1 >= nk) {  // the window holds the whole line
              int any = 0;
              for (int c = 0; c < nk; ++c) any += at(c);
              for (int c = 0; c < nk; ++c) to(base + c * s) = any > 0;
              return;
            }
            int count = 0;
            for (int c = -reach; c <= reach; ++c) count += at(c);
            for (int c = 0; c < nk; ++c) {
              to(base + c * s) = count > 0;
              count += at(c + reach + 1) - at(c - reach);
            }
          });
      from = to;
      stride *= nk;
    }
  }

 private:
  Kokkos::View<char*, memory_space> wet_, near_, wide_, pass_;
  Grid<D> grid_;
  int reach_ = 0;
};

}  // namespace dvisph
