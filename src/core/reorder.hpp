#pragma once
// Reordering of per-particle fields by a permutation (e.g. the cell list's, so that
// particles close in space are close in memory).
#include "src/core/types.hpp"

namespace dvisph {

// out(a, ...) = in(b, ...): one row of a field (rank 1 or 2).
template <class View>
KOKKOS_INLINE_FUNCTION void copy_row(const View& out, int a, const View& in, int b) {
  if constexpr (int(View::traits::rank) == 1) {
    out(a) = in(b);
  } else {
    for (int c = 0; c < static_cast<int>(in.extent(1)); ++c) out(a, c) = in(b, c);
  }
}

// out(a, ...) = in(perm(a), ...) for every row a: reorders a field by a permutation.
template <class Space, class View, class Perm>
void gather_rows(const View& out, const View& in, const Perm& perm) {
  Kokkos::parallel_for(
      "dvisph::gather_rows", Kokkos::RangePolicy<Space>(0, perm.extent(0)),
      KOKKOS_LAMBDA(int a) { copy_row(out, a, in, perm(a)); });
}

// rows(0..m-1) = the rows a < n whose kind(a) is not `drop`, in order; returns m.
template <class Space, class KindView, class Rows>
int rows_not_of_kind(const KindView& kind, Kind drop, int n, const Rows& rows) {
  int m = 0;
  Kokkos::parallel_scan(
      "dvisph::rows_not_of_kind", Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int a, int& offset, bool final) {
        if (kind(a) == drop) return;
        if (final) rows(offset) = a;
        ++offset;
      },
      m);
  return m;
}

}  // namespace dvisph
