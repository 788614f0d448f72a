#pragma once
// Periodic axes of a box: a particle that leaves through one face comes back through the
// opposite one, and a pair is seen at its nearest image. Shared by the grid (cells wrap),
// every neighbour sweep (pair vectors wrap) and the moves (positions wrap).
#include "src/core/types.hpp"

namespace dvisph {

template <int D>
struct Periodic {
  Real lo[D] = {};
  Real length[D] = {};  // 0 along an axis that does not wrap

  Periodic() = default;
  // axes: bit k set when axis k wraps over [lo[k], hi[k])
  Periodic(const Vec<D>& box_lo, const Vec<D>& box_hi, unsigned axes) {
    for (int k = 0; k < D; ++k) {
      lo[k] = box_lo[k];
      length[k] = (axes >> k) & 1u ? box_hi[k] - box_lo[k] : 0;
    }
  }

  KOKKOS_INLINE_FUNCTION bool wraps(int k) const { return length[k] > 0; }

  // xij = xi - xj at its nearest image (unchanged along axes that do not wrap).
  KOKKOS_INLINE_FUNCTION void nearest_image(Vec<D>& xij) const {
    for (int k = 0; k < D; ++k)
      if (wraps(k)) xij[k] = nearest(xij[k], k);
  }
  // Component k of a pair vector at its nearest image, along an axis that wraps.
  KOKKOS_INLINE_FUNCTION Real nearest(Real dx, int k) const {
    return dx - length[k] * math::floor(dx / length[k] + 0.5);
  }
  // x along axis k brought back into [lo, lo + length).
  KOKKOS_INLINE_FUNCTION Real wrap(Real x, int k) const {
    if (!wraps(k)) return x;
    const Real y = x - length[k] * math::floor((x - lo[k]) / length[k]);
    return y < lo[k] + length[k] ? y : lo[k];  // round-off at the upper face
  }
};

}  // namespace dvisph
