#pragma once
// Rigid-body rotation in D dimensions. A 3D bead spins about any axis; a 2D bead is a
// sphere moving in a plane, so it spins about z only and its angular velocity (and any
// torque on it) has one component.
#include "src/core/types.hpp"

namespace dvisph::dem {

template <int D>
constexpr int rot_dim = D == 3 ? 3 : 1;

template <int D>
using Rot = Vec<rot_dim<D>>;

KOKKOS_INLINE_FUNCTION Vec<3> cross(const Vec<3>& a, const Vec<3>& b) {
  Vec<3> c;
  c[0] = a[1] * b[2] - a[2] * b[1];
  c[1] = a[2] * b[0] - a[0] * b[2];
  c[2] = a[0] * b[1] - a[1] * b[0];
  return c;
}
// (w ez) x r: velocity of the point at offset r on a body spinning at w about z.
KOKKOS_INLINE_FUNCTION Vec<2> cross(const Vec<1>& w, const Vec<2>& r) {
  Vec<2> c;
  c[0] = -w[0] * r[1];
  c[1] = w[0] * r[0];
  return c;
}
// z component of r x f: torque about z of a force f applied at offset r.
KOKKOS_INLINE_FUNCTION Vec<1> cross(const Vec<2>& r, const Vec<2>& f) {
  Vec<1> c;
  c[0] = r[0] * f[1] - r[1] * f[0];
  return c;
}

}  // namespace dvisph::dem
