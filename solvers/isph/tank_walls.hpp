#pragma once
// The tank's walls as the pressure solve sees them: each wall particle's inward normal,
// taken from the tank's inner faces (a particle in an edge or corner gets the diagonal;
// particles inside the tank, e.g. a gate, get none).
#include "src/scene.hpp"
#include "src/types.hpp"

namespace dvisph {

template <int D>
struct TankWalls {
  Vec<D> lo, hi;  // inner faces

  KOKKOS_INLINE_FUNCTION Vec<D> inward_normal(const Vec<D>& x) const {
    Vec<D> n;
    Real nn = 0;
    for (int k = 0; k < D; ++k) {
      n[k] = x[k] < lo[k] ? lo[k] - x[k] : x[k] > hi[k] ? hi[k] - x[k] : 0;
      nn += n[k] * n[k];
    }
    const Real scale = nn > 0 ? 1 / math::sqrt(nn) : 0;
    for (int k = 0; k < D; ++k) n[k] *= scale;
    return n;
  }
};

template <int D>
TankWalls<D> tank_walls(const Box& tank) {
  TankWalls<D> w;
  for (int k = 0; k < D; ++k) w.lo[k] = tank.lo[k], w.hi[k] = tank.hi[k];
  return w;
}

}  // namespace dvisph
