#pragma once
// The tank's walls as geometry: each wall particle's inward normal, taken from the
// tank's inner faces (a particle in an edge or corner gets the diagonal; particles
// inside the tank, e.g. a gate, get none), for the pressure solve's wall condition; and
// how deep a point lies inside the walls, for the wall-penetration figure.
#include "src/scene.hpp"
#include "src/types.hpp"

namespace dvisph {

template <int D>
struct TankWalls {
  Vec<D> lo, hi;  // inner faces
  bool open_top;  // no wall on the upper face of the last axis

  // Per axis, how far x lies past a face, pointing back inside (0 within the faces).
  KOKKOS_INLINE_FUNCTION Vec<D> back_inside(const Vec<D>& x) const {
    Vec<D> v;
    for (int k = 0; k < D; ++k) v[k] = x[k] < lo[k] ? lo[k] - x[k] : x[k] > hi[k] ? hi[k] - x[k] : 0;
    return v;
  }

  KOKKOS_INLINE_FUNCTION Vec<D> inward_normal(const Vec<D>& x) const {
    Vec<D> n = back_inside(x);
    const Real nn = dot(n, n), scale = nn > 0 ? 1 / math::sqrt(nn) : 0;
    for (int k = 0; k < D; ++k) n[k] *= scale;
    return n;
  }

  // How deep a point lies inside the walls (0 if not): past a face, and not above an
  // open top (a splash that flew over a wall is not in it).
  KOKKOS_INLINE_FUNCTION Real depth_inside(const Vec<D>& x) const {
    if (open_top && x[D - 1] > hi[D - 1]) return 0;
    const Vec<D> v = back_inside(x);
    Real depth = 0;
    for (int k = 0; k < D; ++k) depth = math::max(depth, math::abs(v[k]));
    return depth;
  }
};

template <int D>
TankWalls<D> tank_walls(const Scene& s) {
  TankWalls<D> w;
  for (int k = 0; k < D; ++k) w.lo[k] = s.tank.lo[k], w.hi[k] = s.tank.hi[k];
  w.open_top = s.open_top;
  return w;
}

}  // namespace dvisph
