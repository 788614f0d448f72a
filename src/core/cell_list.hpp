#pragma once
// Binning of particles into the cells of a Grid, as Kokkos kernels:
// count -> prefix sum -> place -> order within each cell by particle index.
// The last stage makes the layout independent of thread scheduling, so every
// neighbour sweep visits pairs in the same order on every backend (bitwise
// reproducible sums on a given backend, and Serial/OpenMP agreement).
#include "src/core/grid.hpp"

namespace dvisph {

template <int D, class Space>
class CellList {
 public:
  using memory_space = typename Space::memory_space;

  CellList() = default;
  explicit CellList(const Grid<D>& grid)
      : grid_(grid),
        offsets_("dvisph::cell_list::offsets", grid.size() + 1),
        counts_("dvisph::cell_list::counts", grid.size()) {}

  // Bins the first n rows of x (an n x D view in memory_space).
  template <class XView>
  void build(const XView& x, int n) {
    if (static_cast<int>(permutation_.extent(0)) < n) {
      permutation_ = Kokkos::View<int*, memory_space>(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, "dvisph::cell_list::permutation"), n);
      cell_of_ = Kokkos::View<int*, memory_space>(
          Kokkos::view_alloc(Kokkos::WithoutInitializing, "dvisph::cell_list::cell_of"), n);
    }
    n_ = n;
    const Grid<D> grid = grid_;
    auto counts = counts_;
    auto offsets = offsets_;
    auto cell_of = cell_of_;
    auto perm = permutation_;
    const int ncells = grid.size();
    Kokkos::deep_copy(Space(), counts, 0);

    Kokkos::parallel_for(
        "dvisph::cell_list::count", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          Real xi[D];
          for (int k = 0; k < D; ++k) xi[k] = x(i, k);
          const int c = grid.cell_of(xi);
          cell_of(i) = c;
          Kokkos::atomic_increment(&counts(c));
        });
    Kokkos::parallel_scan(
        "dvisph::cell_list::prefix_sum", Kokkos::RangePolicy<Space>(0, ncells),
        KOKKOS_LAMBDA(int c, int& partial, bool final) {
          if (final) offsets(c) = partial;
          partial += counts(c);
          if (final && c == ncells - 1) offsets(ncells) = partial;
        });
    Kokkos::deep_copy(Space(), counts, 0);
    Kokkos::parallel_for(
        "dvisph::cell_list::place", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          const int c = cell_of(i);
          perm(offsets(c) + Kokkos::atomic_fetch_add(&counts(c), 1)) = i;
        });
    Kokkos::parallel_for(
        "dvisph::cell_list::order_within_cells", Kokkos::RangePolicy<Space>(0, ncells),
        KOKKOS_LAMBDA(int c) {
          // insertion sort: cells hold a handful of particles
          for (int a = offsets(c) + 1; a < offsets(c + 1); ++a) {
            const int v = perm(a);
            int b = a - 1;
            for (; b >= offsets(c) && perm(b) > v; --b) perm(b + 1) = perm(b);
            perm(b + 1) = v;
          }
        });
  }

  const Grid<D>& grid() const { return grid_; }
  int size() const { return n_; }
  std::size_t bytes() const { return view_bytes(offsets_, counts_, permutation_, cell_of_); }
  // Particle indices ordered by cell: a permutation that sorts particles for locality.
  Kokkos::View<int*, memory_space> permutation() const {
    return Kokkos::subview(permutation_, Kokkos::make_pair(0, n_));
  }
  Kokkos::View<const int*, memory_space> offsets() const { return offsets_; }

 private:
  Grid<D> grid_;
  int n_ = 0;
  Kokkos::View<int*, memory_space> offsets_, counts_, permutation_, cell_of_;
};

}  // namespace dvisph
