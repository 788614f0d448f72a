#pragma once
// What the contact kernels read of a bead, packed in one row per bead: centre, radius,
// the half-step velocities (translation and spin) over the drift before the force
// sample, and the predicted ones over the drift after it (method: linear_spring_dashpot.hpp).
// A pair reads its partner's row as 16 contiguous doubles (3D: two cache lines) rather
// than from seven arrays; kick_drift writes the rows as it moves the beads.
#include "solvers/dem/rotation.hpp"

namespace dvisph::dem {

template <int D, class Space>
struct ContactKinematics {
  using memory_space = typename Space::memory_space;
  static constexpr int R = rot_dim<D>;
  // centre and radius first: a listed pair that does not touch reads one cache line
  static constexpr int x0 = 0, r0 = D, v0 = D + 1, va0 = 2 * D + 1, w0 = 3 * D + 1, wa0 = 3 * D + R + 1;
  static constexpr int width = 3 * D + 2 * R + 1;

  Kokkos::View<Real* [width], memory_space> row;

  ContactKinematics() = default;
  explicit ContactKinematics(int n)
      : row(Kokkos::view_alloc(Kokkos::WithoutInitializing, "dvisph::dem::contact_kinematics"), n) {}

  KOKKOS_INLINE_FUNCTION Vec<D> x(int i) const { return columns<D>(row, i, x0); }
  KOKKOS_INLINE_FUNCTION Vec<D> v(int i) const { return columns<D>(row, i, v0); }
  KOKKOS_INLINE_FUNCTION Vec<D> v_ahead(int i) const { return columns<D>(row, i, va0); }
  KOKKOS_INLINE_FUNCTION Rot<D> omega(int i) const { return columns<R>(row, i, w0); }
  KOKKOS_INLINE_FUNCTION Rot<D> omega_ahead(int i) const { return columns<R>(row, i, wa0); }
  KOKKOS_INLINE_FUNCTION Real radius(int i) const { return row(i, r0); }
};

}  // namespace dvisph::dem
