#pragma once
// A stored neighbour list, built from a CellSweep and then swept many times in one
// step (e.g. by the CG iterations). Same for_each interface as CellSweep, same pair
// order, so the two are interchangeable in every kernel.
//
// Layout: row i holds its entries at starts(i) .. ends(i) - 1 and has room up to
// limits(i). A full build counts the rows that may be wanted soon (`roomy`, a superset
// of the wanted ones), gives each its count plus some slack (`slack`) in row order,
// keeps a pool behind them, and fills the wanted ones: two sweeps over the cells. The
// next build fills the rows in place in one sweep (particles move a fraction of a
// spacing per step, so counts change by a few); a row that outgrows its room, or a
// wanted row that had none (water reaching a wall), takes new room from the pool, so
// that one such row does not make every row be counted again. Only when the pool is
// spent, or the rows were permuted (forget_layout), does it build in full. The pairs,
// and their order in each row, are the same either way; only where a row sits in
// memory depends on the order rows took pool room in (an atomic counter).
// (3D dam break, dx 3 mm: 8 full builds in 187 steps, 47 without the pool; RESULTS.md.)
#include "src/core/csr_rows.hpp"
#include "src/core/neighbor_sweep.hpp"

#include <stdexcept>

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

  // Row i's room: the targets of `sweep` around query point i and their slack (none
  // if it is not roomy).
  template <class XView, class Roomy>
  struct RoomCount {
    CellSweep<D, Space> sweep;
    XView xq;
    Roomy roomy;
    KOKKOS_INLINE_FUNCTION int operator()(int i) const {
      const int count = roomy(i) ? sweep.count(row<D>(xq, i)) : 0;
      return count > 0 ? count + slack(count) + 1 : 0;  // and the spare slot of `Fill`
    }
  };

  // Row i's entries: the targets of `sweep` around query point i, in sweep order, as
  // many as its room holds but its last slot (CellSweep::collect's spare); a row that
  // does not fit moves to new room from the pool (pool_top .. pool_end) and is filled
  // there. Sums the entries and counts the rows that found no room.
  template <class XView, class Wanted>
  struct Fill {
    CellSweep<D, Space> sweep;
    XView xq;
    Wanted wanted;
    Kokkos::View<int*, memory_space> starts, limits, ends, neighbors;
    Kokkos::View<int, memory_space> out_of_room, pool_top;
    int pool_end;
    using value_type = long;
    KOKKOS_INLINE_FUNCTION void operator()(int i, long& entries) const {
      int first = starts(i);
      const int spare = limits(i) - 1;
      int count = 0;
      if (wanted(i) && spare >= first) count = sweep.collect(row<D>(xq, i), neighbors, first, spare);
      else if (wanted(i))  // no room: it fits if it has no target
        count = sweep.count(row<D>(xq, i));
      bool fits = count == 0 || first + count <= spare;
      if (!fits) {
        const int need = count + slack(count) + 1;
        const int base = Kokkos::atomic_fetch_add(&pool_top(), need);
        if (base + need <= pool_end) {
          first = base;
          starts(i) = base;
          limits(i) = base + need;
          sweep.collect(row<D>(xq, i), neighbors, first, base + need - 1);
          fits = true;
        } else {
          Kokkos::atomic_increment(&out_of_room());
        }
      }
      ends(i) = fits ? first + count : first;
      entries += ends(i) - first;
    }
  };

  // Each row's room ends where the next row's starts in the counted layout.
  struct LayOut {
    Kokkos::View<int*, memory_space> starts, limits;
    KOKKOS_INLINE_FUNCTION void operator()(int i) const { limits(i) = starts(i + 1); }
  };

  // Room beyond a row's count at a full build: what a step's motion may add.
  KOKKOS_INLINE_FUNCTION static int slack(int count) { return count > 0 ? 4 + count / 8 : 0; }

  // Lists, for each of the n query points xq(i) with wanted(i), the targets of `sweep`
  // (an empty list for the others); rows with roomy(i) get room at a full build, where
  // roomy = make_roomy() is asked for (only then: it may cost a pass of its own).
  template <class XView, class Wanted, class MakeRoomy>
  void build(const CellSweep<D, Space>& sweep, const XView& xq, int n, const Wanted& wanted,
             const MakeRoomy& make_roomy) {
    if (n != n_ || static_cast<int>(ends_.extent(0)) < n) forget_layout();
    if (!(laid_out_ && fill(sweep, xq, n, wanted))) {
      // the counted layout: row starts as CSR offsets (rows that move later overwrite theirs)
      const auto roomy = make_roomy();
      const int room = csr_offsets<Space>(starts_, n, RoomCount<XView, decltype(roomy)>{sweep, xq, roomy},
                                          "dvisph::neighbor_list");
      reserve_entries(neighbors_, room + room / 16 + 256, "dvisph::neighbor_list::neighbors");
      const auto none = Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string("dvisph::neighbor_list::rows"));
      if (static_cast<int>(ends_.extent(0)) < n) {
        ends_ = Kokkos::View<int*, memory_space>(none, n);
        limits_ = Kokkos::View<int*, memory_space>(none, n);
      }
      Kokkos::parallel_for("dvisph::neighbor_list::lay_out", Kokkos::RangePolicy<Space>(0, n),
                           LayOut{starts_, limits_});
      Kokkos::deep_copy(Space(), pool_top_, room);
      room_ = room;
      if (!fill(sweep, xq, n, wanted)) throw std::logic_error("NeighborList: a counted row overflowed");
      ++full_builds_;
    }
    n_ = n;
    laid_out_ = true;
    x_ = sweep.x;
    radius2_ = sweep.radius2;
    periodic_ = sweep.grid.periodic;
  }

  template <class XView, class Wanted>
  void build(const CellSweep<D, Space>& sweep, const XView& xq, int n, const Wanted& wanted) {
    build(sweep, xq, n, wanted, [&] { return wanted; });
  }
  template <class XView>
  void build(const CellSweep<D, Space>& sweep, const XView& xq, int n) {
    build(sweep, xq, n, Everyone{});
  }

  // The rows no longer belong to the same query points (they were permuted): the next
  // build counts them afresh.
  void forget_layout() { laid_out_ = false; }

  struct Sweep {
    using execution_space = Space;
    Kokkos::View<const int*, memory_space> starts, ends, neighbors;
    Kokkos::View<const Real* [D], memory_space> x;
    Real radius2;
    Periodic<D> periodic;
    // Positions may have moved since the build: distances are recomputed, and pairs
    // that drifted beyond the radius are skipped (a list built with a skin stays valid).
    template <class F>
    KOKKOS_INLINE_FUNCTION void for_each(int i, const Vec<D>& xi, F&& f) const {
      for (int a = starts(i); a < ends(i); ++a) visit_within(x, neighbors(a), xi, radius2, periodic, f);
    }
  };
  // The sweep over stored pairs; `radius` may be smaller than the build radius.
  Sweep sweep(Real radius) const { return Sweep{starts_, ends_, neighbors_, x_, radius * radius, periodic_}; }
  Sweep sweep() const { return Sweep{starts_, ends_, neighbors_, x_, radius2_, periodic_}; }

  long pairs() const { return pairs_; }
  // builds that counted the rows (the others filled them in place)
  long full_builds() const { return full_builds_; }
  // entries of the pool that rows have taken since the last full build
  long pool_entries() const {
    int top = 0;
    Kokkos::deep_copy(top, pool_top_);
    return top - room_;
  }
  std::size_t bytes() const {
    return view_bytes(starts_, limits_, ends_, neighbors_, out_of_room_, pool_top_);
  }

 private:
  // Fills the rows in their room; false if one did not fit (the list is then unusable).
  template <class XView, class Wanted>
  bool fill(const CellSweep<D, Space>& sweep, const XView& xq, int n, const Wanted& wanted) {
    Kokkos::deep_copy(Space(), out_of_room_, 0);
    long entries = 0;
    Kokkos::parallel_reduce("dvisph::neighbor_list::fill", RowPolicy<Space>(0, n),
                            Fill<XView, Wanted>{sweep, xq, wanted, starts_, limits_, ends_, neighbors_,
                                                out_of_room_, pool_top_,
                                                static_cast<int>(neighbors_.extent(0))},
                            entries);
    int out = 0;
    Kokkos::deep_copy(out, out_of_room_);
    pairs_ = entries;
    return out == 0;
  }

  int n_ = -1;
  bool laid_out_ = false;
  long pairs_ = 0, full_builds_ = 0;
  int room_ = 0;  // entries of the counted layout; the pool follows them
  Kokkos::View<int, memory_space> out_of_room_{"dvisph::neighbor_list::out_of_room"};
  Kokkos::View<int, memory_space> pool_top_{"dvisph::neighbor_list::pool_top"};  // its next free entry
  Real radius2_ = 0;
  Kokkos::View<int*, memory_space> starts_, limits_, ends_, neighbors_;
  Kokkos::View<const Real* [D], memory_space> x_;
  Periodic<D> periodic_;
};

}  // namespace dvisph
