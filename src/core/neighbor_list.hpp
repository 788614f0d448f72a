#pragma once
// A stored neighbour list (CSR), built once from a CellSweep and then swept many
// times in one step (e.g. by the CG iterations). Same for_each interface as
// CellSweep, same pair order, so the two are interchangeable in every kernel.
#include "src/core/csr_rows.hpp"
#include "src/core/neighbor_sweep.hpp"

namespace dvisph {

template <int D, class Space>
class NeighborList {
 public:
  struct Everyone {
    KOKKOS_INLINE_FUNCTION bool operator()(int) const { return true; }
  };

  using memory_space = typename Space::memory_space;

  // The build's kernels are functors, not KOKKOS_LAMBDAs: with nvcc (CUDA 13), the host
  // side of a device lambda here crashed (a null copy function in nvcc's lambda
  // wrapper) when two test files instantiated build<..., Everyone>.

  // Row i's length: the targets of `sweep` around query point i, none if not wanted.
  template <class XView, class Wanted>
  struct TargetCount {
    CellSweep<D, Space> sweep;
    XView xq;
    Wanted wanted;
    KOKKOS_INLINE_FUNCTION int operator()(int i) const {
      int count = 0;
      if (wanted(i)) sweep.for_each(i, row<D>(xq, i), [&](int, const Vec<D>&, Real) { ++count; });
      return count;
    }
  };

  // Row i's entries: the targets of `sweep` around query point i, in sweep order.
  template <class XView>
  struct TargetFill {
    CellSweep<D, Space> sweep;
    XView xq;
    Kokkos::View<int*, memory_space> offsets, neighbors;
    KOKKOS_INLINE_FUNCTION void operator()(int i) const {
      int a = offsets(i);
      if (a == offsets(i + 1)) return;
      sweep.for_each(i, row<D>(xq, i), [&](int j, const Vec<D>&, Real) { neighbors(a++) = j; });
    }
  };

  // Lists, for each of the n query points xq(i) with wanted(i), the targets of `sweep`
  // (an empty list for the others).
  template <class XView, class Wanted>
  void build(const CellSweep<D, Space>& sweep, const XView& xq, int n, const Wanted& wanted) {
    const int total = csr_offsets<Space>(offsets_, n, TargetCount<XView, Wanted>{sweep, xq, wanted},
                                         "dvisph::neighbor_list");
    reserve_entries(neighbors_, total, "dvisph::neighbor_list::neighbors");
    Kokkos::parallel_for("dvisph::neighbor_list::fill", Kokkos::RangePolicy<Space>(0, n),
                         TargetFill<XView>{sweep, xq, offsets_, neighbors_});
    n_ = n;
    pairs_ = total;
    x_ = sweep.x;
    radius2_ = sweep.radius2;
    periodic_ = sweep.grid.periodic;
  }

  template <class XView>
  void build(const CellSweep<D, Space>& sweep, const XView& xq, int n) {
    build(sweep, xq, n, Everyone{});
  }

  struct Sweep {
    using execution_space = Space;
    Kokkos::View<const int*, memory_space> offsets, neighbors;
    Kokkos::View<const Real* [D], memory_space> x;
    Real radius2;
    Periodic<D> periodic;
    // Positions may have moved since the build: distances are recomputed, and pairs
    // that drifted beyond the radius are skipped (a list built with a skin stays valid).
    template <class F>
    KOKKOS_INLINE_FUNCTION void for_each(int i, const Vec<D>& xi, F&& f) const {
      for (int a = offsets(i); a < offsets(i + 1); ++a) visit_within(x, neighbors(a), xi, radius2, periodic, f);
    }
  };
  // The sweep over stored pairs; `radius` may be smaller than the build radius.
  Sweep sweep(Real radius) const { return Sweep{offsets_, neighbors_, x_, radius * radius, periodic_}; }
  Sweep sweep() const { return Sweep{offsets_, neighbors_, x_, radius2_, periodic_}; }

  long pairs() const { return pairs_; }
  std::size_t bytes() const { return view_bytes(offsets_, neighbors_); }

 private:
  int n_ = 0;
  long pairs_ = 0;
  Real radius2_ = 0;
  Kokkos::View<int*, memory_space> offsets_, neighbors_;
  Kokkos::View<const Real* [D], memory_space> x_;
  Periodic<D> periodic_;
};

}  // namespace dvisph
