#pragma once
// Reordering of per-particle fields by a permutation (e.g. the cell list's, so that
// particles close in space are close in memory).
#include "src/types.hpp"

namespace dvisph {

// out(a, ...) = in(perm(a), ...) for every row a: reorders a field by a permutation.
template <class Space, class View, class Perm>
void gather_rows(const View& out, const View& in, const Perm& perm) {
  const int ncols = View::traits::rank == 1 ? 1 : static_cast<int>(in.extent(1));
  Kokkos::parallel_for(
      "dvisph::gather_rows", Kokkos::RangePolicy<Space>(0, perm.extent(0)), KOKKOS_LAMBDA(int a) {
        if constexpr (int(View::traits::rank) == 1) {
          out(a) = in(perm(a));
        } else {
          for (int c = 0; c < ncols; ++c) out(a, c) = in(perm(a), c);
        }
      });
}

}  // namespace dvisph
