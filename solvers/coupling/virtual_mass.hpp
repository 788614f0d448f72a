#pragma once
// Virtual-mass coefficient C_r(eps) = 1 + 0.34 (1 - eps) / eps (van Gent 1995, as in
// Shao 2010's porous ISPH): water in a bed accelerates with part of the grains around it.
// `off` gives C_r = 1 (coupling.virtual_mass: none).
#include "src/core/types.hpp"

namespace dvisph {

struct VanGentVirtualMass {
  bool on = true;
  KOKKOS_INLINE_FUNCTION Real operator()(Real eps) const {
    return on ? 1 + 0.34 * (1 - eps) / eps : Real(1);
  }
};

}  // namespace dvisph
