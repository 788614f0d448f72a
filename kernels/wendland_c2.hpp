#pragma once
// Wendland C2 kernel (Wendland 1995; Dehnen & Aly 2012), support radius 2h.
#include "src/core/types.hpp"

namespace dvisph {

template <int D>
struct WendlandC2 {
  static constexpr const char* name = "wendland_c2";
  static constexpr int dim = D;
  Real h, inv_h, sigma;

  explicit WendlandC2(Real h_) : h(h_), inv_h(1.0 / h_) {
    sigma = (D == 2 ? 7.0 / (4.0 * math::pi) : 21.0 / (16.0 * math::pi));
    for (int k = 0; k < D; ++k) sigma *= inv_h;
  }
  KOKKOS_INLINE_FUNCTION Real radius() const { return 2 * h; }

  // W = sigma (1 - q/2)^4 (2q + 1), q = r/h < 2
  KOKKOS_INLINE_FUNCTION Real W(Real r) const {
    const Real q = r * inv_h;
    if (q >= 2) return 0;
    const Real t = 1 - 0.5 * q;
    const Real t2 = t * t;
    return sigma * t2 * t2 * (2 * q + 1);
  }
  // dW/dr / r = -5 sigma q (1 - q/2)^3 / (h r) = -5 sigma (1 - q/2)^3 / h^2
  KOKKOS_INLINE_FUNCTION Real dW_over_r(Real r) const {
    const Real q = r * inv_h;
    if (q >= 2) return 0;
    const Real t = 1 - 0.5 * q;
    return -5 * sigma * t * t * t * inv_h * inv_h;
  }
  KOKKOS_INLINE_FUNCTION Vec<D> grad(const Vec<D>& xij, Real r) const {
    return dW_over_r(r) * xij;
  }
};

}  // namespace dvisph
