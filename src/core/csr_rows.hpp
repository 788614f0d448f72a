#pragma once
// The row layout of a compressed sparse row (CSR) structure, shared by the stored
// neighbour list and the stored PPE matrix: count each row's entries, prefix-sum the
// counts into offsets, size the entry arrays.
#include "src/core/types.hpp"

#include <string>

namespace dvisph {

// offsets(i) .. offsets(i + 1) - 1 index row i's count(i) entries, i < n (offsets grows to
// n + 1 when smaller). Kernels are named `name`::count and `name`::prefix_sum. Returns
// the number of entries. `count` is a functor (see NeighborList::build for why not a
// KOKKOS_LAMBDA).
template <class Space, class Count>
int csr_offsets(Kokkos::View<int*, typename Space::memory_space>& offsets, int n,
                const Count& count, const std::string& name) {
  if (static_cast<int>(offsets.extent(0)) < n + 1)
    offsets = Kokkos::View<int*, typename Space::memory_space>(name + "::offsets", n + 1);
  auto o = offsets;
  Kokkos::parallel_for(
      name + "::count", RowPolicy<Space>(0, n), KOKKOS_LAMBDA(int i) { o(i + 1) = count(i); });
  int total = 0;
  Kokkos::parallel_scan(
      name + "::prefix_sum", Kokkos::RangePolicy<Space>(0, n + 1),
      KOKKOS_LAMBDA(int i, int& partial, bool final) {
        partial += (i == 0 ? 0 : o(i));
        if (final) o(i) = partial;
      },
      total);
  return total;
}

// Grows an entry array to hold `total`, with slack so that a slowly growing count does
// not reallocate every step.
template <class View>
void reserve_entries(View& entries, int total, const std::string& label) {
  if (static_cast<int>(entries.extent(0)) < total)
    entries = View(Kokkos::view_alloc(Kokkos::WithoutInitializing, label), total + total / 8);
}

}  // namespace dvisph
