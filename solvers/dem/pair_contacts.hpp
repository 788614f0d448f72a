#pragma once
// What the contact kernel leaves at each listed bead pair (i, j), i < j, for bead j to
// gather (src/core/half_pairs.hpp): whether the two touch and, if they do, the force on i, the
// moment n x F (the torque on either bead is minus its radius times it, n from j to i),
// and i's tangential displacement. Bead j takes the opposite force and displacement.
// One row of F, n x F and xi per entry, so the gather reads one contiguous record.
#include "solvers/dem/rotation.hpp"

#include <string>

namespace dvisph::dem {

template <int D, class Space>
struct PairContacts {
  using memory_space = typename Space::memory_space;
  static constexpr int R = rot_dim<D>;
  static constexpr int force = 0, moment = D, xi = D + R, width = 2 * D + R;  // columns

  Kokkos::View<Real* [width], memory_space> record;
  Kokkos::View<char*, memory_space> touching;

  // Room for `entries` list entries (kept when there is enough).
  void reserve(int entries) {
    if (static_cast<int>(touching.extent(0)) >= entries) return;
    const int size = entries + entries / 8;
    record = decltype(record)(Kokkos::view_alloc(Kokkos::WithoutInitializing, "dvisph::dem::pair_record"), size);
    touching = decltype(touching)(Kokkos::view_alloc(Kokkos::WithoutInitializing, "dvisph::dem::pair_touching"), size);
  }

  KOKKOS_INLINE_FUNCTION void set(int a, const Vec<D>& f, const Rot<D>& m, const Vec<D>& x) const {
    for (int k = 0; k < D; ++k) record(a, force + k) = f[k];
    for (int c = 0; c < R; ++c) record(a, moment + c) = m[c];
    for (int k = 0; k < D; ++k) record(a, xi + k) = x[k];
    touching(a) = 1;
  }
  template <int N>
  KOKKOS_INLINE_FUNCTION Vec<N> get(int a, int first) const {
    Vec<N> r;
    for (int k = 0; k < N; ++k) r[k] = record(a, first + k);
    return r;
  }
  std::size_t bytes() const { return record.span() * sizeof(Real) + touching.span(); }
};

}  // namespace dvisph::dem
