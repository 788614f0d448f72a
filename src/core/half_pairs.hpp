#pragma once
// A symmetric stored neighbour list (j is in row i exactly when i is in row j, as a
// list of one set within one radius is) split so that a pair kernel evaluates each pair
// once: `upper` row i holds the partners j > i, in the list's order, and a kernel stores
// what it finds for pair (i, j) at that entry; `lower` row i holds the partners j < i,
// in ascending order, each with the upper entry where pair (j, i) is stored, and each
// upper entry names its `mirror`, the lower entry of the same pair. A particle then adds
// its upper pairs and gathers its lower ones in a fixed order: half the pair work, no
// atomics, and the same sums in the same order on every backend. What the other particle
// gathers is best written at the mirror, so that the gather reads its rows in order; the
// ascending order makes that gather the same sum as one the partners add to in turn, a
// kernel visiting the particles in index order.
#include "src/core/csr_rows.hpp"

#include <stdexcept>

namespace dvisph {

template <class Space>
class HalfPairs {
 public:
  using memory_space = typename Space::memory_space;
  using Ints = Kokkos::View<int*, memory_space>;

  struct Rows {
    Kokkos::View<const int*, memory_space> upper_offsets, upper, mirror, lower_offsets, lower, lower_entry;
  };

  // The build's kernels are functors, for the reason NeighborList gives.
  template <class List, bool Above>
  struct Count {
    List list;
    KOKKOS_INLINE_FUNCTION int operator()(int i) const {
      int count = 0;
      for (int a = list.starts(i); a < list.ends(i); ++a) {
        const int j = list.neighbors(a);
        count += Above ? j > i : j < i;
      }
      return count;
    }
  };
  template <class List>
  struct Fill {
    List list;
    Ints upper_offsets, upper, mirror, lower_offsets, lower, lower_entry;
    Kokkos::View<int, memory_space> unmatched;
    KOKKOS_INLINE_FUNCTION void operator()(int i) const {
      int u = upper_offsets(i);
      for (int a = list.starts(i); a < list.ends(i); ++a) {
        const int j = list.neighbors(a);
        if (j > i) {
          upper(u++) = j;
        } else if (j < i) {
          // j's rank among i's lower partners (quadratic in the row, whose length is a
          // bead's few neighbours: cheap next to the search for the mirror below)
          int l = lower_offsets(i);
          for (int b = list.starts(i); b < list.ends(i); ++b) l += list.neighbors(b) < j;
          // where row j's upper part holds i: row j's partners above j, in list order
          int e = upper_offsets(j), found = -1;
          for (int b = list.starts(j); b < list.ends(j) && found < 0; ++b) {
            const int k = list.neighbors(b);
            if (k == i) found = e;
            e += k > j;
          }
          if (found < 0)
            Kokkos::atomic_increment(&unmatched());
          else
            mirror(found) = l;
          lower(l) = j;
          lower_entry(l) = found;
        }
      }
    }
  };

  // `list`: a NeighborList sweep (offsets, neighbors) over n rows.
  template <class List>
  void build(const List& list, int n) {
    const int up = csr_offsets<Space>(upper_offsets_, n, Count<List, true>{list}, "dvisph::half_pairs::upper");
    const int lo = csr_offsets<Space>(lower_offsets_, n, Count<List, false>{list}, "dvisph::half_pairs::lower");
    if (up != lo) throw std::logic_error("HalfPairs: the neighbour list is not symmetric");
    reserve_entries(upper_, up, "dvisph::half_pairs::upper");
    reserve_entries(mirror_, up, "dvisph::half_pairs::mirror");
    reserve_entries(lower_, lo, "dvisph::half_pairs::lower");
    reserve_entries(lower_entry_, lo, "dvisph::half_pairs::lower_entry");
    Kokkos::deep_copy(unmatched_, 0);
    Kokkos::parallel_for("dvisph::half_pairs::fill", Kokkos::RangePolicy<Space>(0, n),
                         Fill<List>{list, upper_offsets_, upper_, mirror_, lower_offsets_, lower_, lower_entry_, unmatched_});
    int missing = 0;
    Kokkos::deep_copy(missing, unmatched_);
    if (missing != 0) throw std::logic_error("HalfPairs: the neighbour list is not symmetric");
    pairs_ = up;
  }

  Rows rows() const { return {upper_offsets_, upper_, mirror_, lower_offsets_, lower_, lower_entry_}; }
  int pairs() const { return pairs_; }  // upper entries: each pair once

 private:
  Ints upper_offsets_, upper_, mirror_, lower_offsets_, lower_, lower_entry_;
  Kokkos::View<int, memory_space> unmatched_{"dvisph::half_pairs::unmatched"};  // once, not per build
  int pairs_ = 0;
};

}  // namespace dvisph
