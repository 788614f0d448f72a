#pragma once
// What a fluid particle's equations take from the solids around it (method.md §2 and
// eq. 5): the porosity eps_i, which sets its reference density eps_i rho_f and its
// volume V_i = m_i / (eps_i rho_f), and the virtual-mass coefficient C_r(eps_i). Every
// ISPH kernel reads them through a medium, so one source serves clear water and beds:
//   porosity(i)            eps_i
//   volume_ratio(j)        V_j / V_ref, V_ref = dx^D the volume of a lattice particle
//                          (every particle is made with mass rho_f V_ref)
//   pair_coefficient(i, j) the PPE's symmetric pair coefficient, 2 / (C_r,i + C_r,j)
//                          (the harmonic mean of 1 / C_r: the corrector moves particle
//                          i by dt / (C_r,i rho_f) grad P, and a pair coefficient that
//                          depends on i and j alike keeps the PPE matrix symmetric)
//   inverse_virtual_mass(i) 1 / C_r,i
// Clear water is the medium whose values are the constants eps = 1, C_r = 1, so a
// water-only scene holds and reads no such fields, and multiplying by them is exact:
// clear-water results are bit-identical to a solver without media.
#include "src/types.hpp"

namespace dvisph {

struct ClearWater {
  KOKKOS_INLINE_FUNCTION Real porosity(int) const { return 1; }
  KOKKOS_INLINE_FUNCTION Real volume_ratio(int) const { return 1; }
  KOKKOS_INLINE_FUNCTION Real pair_coefficient(int, int) const { return 1; }
  KOKKOS_INLINE_FUNCTION Real inverse_virtual_mass(int) const { return 1; }
};

}  // namespace dvisph
