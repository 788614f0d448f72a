#pragma once
// Drag closure of Di Felice (1994), the default of CFDEM's unresolved coupling: one
// bead's drag C_d pi d^2/8 rho eps^2 |u| u eps^-chi with C_d = (0.63 + 4.8/sqrt(Re))^2
// (Dallavalle), Re = eps rho |u| d / mu and chi = 3.7 - 0.65 exp(-(1.5 - log10 Re)^2/2),
// spread over the beads' share of the volume. Returns the momentum-exchange coefficient
// K [kg/(m^3 s)] (drag on the fluid per unit volume -K (u_f - u_s), as ErgunWenYu).
// Its C_d is larger than Schiller-Naumann's at the Reynolds numbers of a settling
// 2.7 mm glass bead, so the terminal velocities differ (docs/coupling.md).
#include "src/core/types.hpp"

namespace dvisph {

struct DiFelice {
  Real rho, mu, d;

  KOKKOS_INLINE_FUNCTION Real operator()(Real eps, Real slip) const {
    const Real re = math::max(eps * rho * slip * d / mu, Real(1e-12));
    const Real sqrt_re = math::sqrt(re);
    const Real a = 0.63 * sqrt_re + 4.8;  // C_d Re = a^2: finite as the slip goes to 0
    const Real cd_slip = a * a * mu / (eps * rho * d);
    const Real lg = 1.5 - math::log10(re);
    const Real chi = 3.7 - 0.65 * math::exp(-0.5 * lg * lg);
    return 0.75 * cd_slip * rho * eps * eps * (1 - eps) / d * math::pow(eps, -chi);
  }
};

}  // namespace dvisph
