#pragma once
// A damped start (numerics.settle_until, settle_time): while t < settle_until each fluid
// particle's velocity relaxes as v <- v exp(-dt / settle_time) after the corrector. Water
// set on a lattice is not at the discrete equilibrium of the SPH operators (the summation
// density near walls and the free surface, a bed's porosity), and with nu = 1e-6 m^2/s the
// motion that finds it hardly decays: 3 mm/s rms after 0.5 s in bed_hydrostatic's tank
// without beads. Damped, the water and a bed settle into that equilibrium and the run
// after settle_until is free (docs/coupling.md).
#include "src/core/types.hpp"

namespace dvisph {

template <int D, class Space, class V, class KindV>
void settle_damping(const V& v, const KindV& kind, Real factor, int n) {
  Kokkos::parallel_for(
      "dvisph::isph::settle_damping", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        if (kind(i) != Kind::fluid) return;
        for (int k = 0; k < D; ++k) v(i, k) *= factor;
      });
}

}  // namespace dvisph
