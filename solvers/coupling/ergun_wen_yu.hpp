#pragma once
// Drag closure of Gidaspow (1986): Ergun (1952) in dense beds, Wen & Yu (1966) above
// the switch porosity eps_d (0.8 by default). Returns the momentum-exchange coefficient
// K [kg/(m^3 s)]: the drag on the fluid per unit volume of mixture is -K (u_f - u_s),
// u the intrinsic velocities. In a steady flow through a fixed bed the fluid's share of
// the pressure gradient, eps grad P, balances it, so grad P = -K q / eps^2 with
// q = eps u_f, which is Ergun's law exactly:
//   -dP/dx = 150 mu (1-eps)^2 q / (eps^3 d^2) + 1.75 rho (1-eps) q^2 / (eps^3 d).
// Above eps_d the Wen-Yu form gives one bead in clear water the Schiller-Naumann drag
// C_d pi d^2/8 rho |u| u, times eps^-1.65.
#include "src/core/types.hpp"

namespace dvisph {

struct ErgunWenYu {
  Real rho, mu, d, eps_switch;

  // eps in (0, 1], slip = |u_f - u_s| >= 0
  KOKKOS_INLINE_FUNCTION Real operator()(Real eps, Real slip) const {
    const Real solid = 1 - eps;
    if (eps < eps_switch)
      return 150 * mu * solid * solid / (eps * d * d) + 1.75 * rho * solid * slip / d;
    const Real re = eps * rho * slip * d / mu;
    // C_d |u| written without 1/Re, finite as the slip goes to 0
    const Real cd_slip = re < 1000 ? 24 * mu / (eps * rho * d) * (1 + 0.15 * math::pow(re, 0.687))
                                   : 0.44 * slip;
    return 0.75 * cd_slip * eps * solid * rho / d * math::pow(eps, -2.65);
  }
};

}  // namespace dvisph
