#pragma once
// Cubic B-spline kernel (Monaghan 1992), support radius 2h.
#include "src/core/types.hpp"

namespace dvisph {

template <int D>
struct CubicSpline {
  static constexpr const char* name = "cubic_spline";
  static constexpr int dim = D;
  Real h, inv_h, sigma;

  explicit CubicSpline(Real h_) : h(h_), inv_h(1.0 / h_) {
    sigma = (D == 2 ? 10.0 / (7.0 * math::pi) : 1.0 / math::pi);
    for (int k = 0; k < D; ++k) sigma *= inv_h;
  }
  KOKKOS_INLINE_FUNCTION Real radius() const { return 2 * h; }

  KOKKOS_INLINE_FUNCTION Real W(Real r) const {
    const Real q = r * inv_h;
    if (q >= 2) return 0;
    if (q >= 1) {
      const Real t = 2 - q;
      return sigma * 0.25 * t * t * t;
    }
    return sigma * (1 - 1.5 * q * q + 0.75 * q * q * q);
  }
  // dW/dr divided by r: the gradient is xij times this (finite as r -> 0).
  KOKKOS_INLINE_FUNCTION Real dW_over_r(Real r) const {
    const Real q = r * inv_h;
    if (q >= 2) return 0;
    if (q >= 1) {
      const Real t = 2 - q;
      return -sigma * 0.75 * t * t * inv_h / r;
    }
    return sigma * (-3 + 2.25 * q) * inv_h * inv_h;
  }
  KOKKOS_INLINE_FUNCTION Vec<D> grad(const Vec<D>& xij, Real r) const {
    return dW_over_r(r) * xij;
  }
};

}  // namespace dvisph
