#pragma once
// The tank's walls as geometry: each wall particle's inward normal, taken from the
// tank's inner faces (a particle in an edge or corner gets the diagonal) or, for the
// gate's particles (inside the tank, on the downstream side of its plane), the normal
// of the gate toward the water behind it, for the pressure solve's wall condition; and
// how deep a point lies inside the walls, for the wall-penetration figure. Walls are
// static: the wall condition takes their velocity as 0.
#include "src/scene.hpp"
#include "src/core/types.hpp"

namespace dvisph {

template <int D>
struct TankWalls {
  Vec<D> lo, hi;  // inner faces
  bool open_top;  // no wall on the upper face of the last axis
  bool gate = false;
  Real gate_x = 0;  // the gate's plane, across the first axis (while it stands)

  // Per axis, how far x lies past a face, pointing back inside (0 within the faces).
  KOKKOS_INLINE_FUNCTION Vec<D> back_inside(const Vec<D>& x) const {
    Vec<D> v;
    for (int k = 0; k < D; ++k) v[k] = x[k] < lo[k] ? lo[k] - x[k] : x[k] > hi[k] ? hi[k] - x[k] : 0;
    return v;
  }

  KOKKOS_INLINE_FUNCTION Vec<D> inward_normal(const Vec<D>& x) const {
    Vec<D> n = back_inside(x);
    Real nn = dot(n, n);
    if (nn == 0 && gate && x[0] >= gate_x) n[0] = -1, nn = 1;  // a gate particle
    const Real scale = nn > 0 ? 1 / math::sqrt(nn) : 0;
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
  // a periodic axis has no faces
  for (int k = 0; k < D; ++k) {
    w.lo[k] = s.wraps(k) ? -1e300 : s.tank.lo[k];
    w.hi[k] = s.wraps(k) ? 1e300 : s.tank.hi[k];
  }
  w.open_top = s.open_top;
  if (s.gate) w.gate = true, w.gate_x = s.gate->x;
  return w;
}

}  // namespace dvisph
