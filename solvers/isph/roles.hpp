#pragma once
// Summation density, the role of each particle in the pressure solve, and the weight
// of the density-invariance term:
//  - fluid particles are unknowns; those on the free surface are marked `surface`.
//    The surface test (a scene choice) is the position divergence
//    div r = sum_j V (x_j - x_i).grad W_ij (Lee et al. 2008), which measures how much
//    of the support is empty, or the summation density;
//  - the density-invariance term of a fluid particle is weighted by how full its
//    support is: 1 where div r is at least `invariance_full` of its interior value,
//    0 below `invariance_from`, linear in between (0 on the surface). Where part of
//    the support is air, <rho> is low because of the air, not because the water
//    expanded; read as an error, that deficit made the term compress the water under
//    the surface, the more the larger gamma (docs/stability.md). div r tells the two
//    apart where <rho> cannot (under uniform compression it rises with <rho>), and
//    the ramp keeps particles whose div r scatters about a threshold from switching
//    the term on and off;
//  - wall particles with no fluid neighbour play no part (excluded);
//  - a wall particle to which the water pressure, continued hydrostatically from its
//    fluid neighbours (Shepard average of P_j + rho0 g.(x_w - x_j), last step's P),
//    would be negative lies beside the free surface: Dirichlet P = 0, so that it does
//    not pull the water up the wall; the others are unknowns.
#include "src/types.hpp"

namespace dvisph {

enum class Role : std::uint8_t { excluded = 0, dirichlet = 1, fluid = 2, surface = 3, wall = 4 };

KOKKOS_INLINE_FUNCTION bool in_stencil(Role r) { return r != Role::excluded; }
KOKKOS_INLINE_FUNCTION bool unknown(Role r) { return r >= Role::fluid; }
KOKKOS_INLINE_FUNCTION bool water(Role r) { return r == Role::fluid || r == Role::surface; }

template <int D>
struct SurfaceTest {
  bool by_density;  // else by position divergence
  Real density_threshold, divergence_threshold;  // fractions of the interior values
  Real invariance_from, invariance_full;         // fractions of the interior div r
  Real rho_ref, div_r_ref;                       // interior values of <rho> and div r
  Real rho0;
  Vec<D> g;
};

template <int D, class Sweep, class Kernel, class X, class M, class KindV, class P, class Rho,
          class RoleV, class Weight>
void density_and_roles(const Sweep& sweep, const Kernel& kernel, const X& x, const M& m,
                       const KindV& kind, const P& p_last, Real volume, SurfaceTest<D> test,
                       const Rho& rho, const RoleV& role, const Weight& invariance, int n) {
  using Space = typename Sweep::execution_space;
  // tolerance on the continued pressure: round-off of symmetric sums
  Real gnorm = 0;
  for (int k = 0; k < D; ++k) gnorm += test.g[k] * test.g[k];
  const Real p_tol = 1e-9 * test.rho0 * math::sqrt(gnorm) * kernel.h;
  Kokkos::parallel_for(
      "dvisph::isph::density_and_roles", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        const bool fluid = kind(i) == Kind::fluid;
        Real sum = 0, div_r = 0, w_fluid = 0, p_fluid = 0;
        sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>& xij, Real r) {
          const Real w = kernel.W(r);
          sum += m(j) * w;
          div_r -= volume * kernel.dW_over_r(r) * r * r;
          if (!fluid && kind(j) == Kind::fluid) {
            w_fluid += w;
            p_fluid += w * (p_last(j, 0) + test.rho0 * dot(test.g, xij));
          }
        });
        rho(i) = sum;
        if (fluid) {
          const bool surface = test.by_density ? sum < test.density_threshold * test.rho_ref
                                               : div_r < test.divergence_threshold * test.div_r_ref;
          role(i) = surface ? Role::surface : Role::fluid;
          const Real full = (div_r / test.div_r_ref - test.invariance_from) /
                            (test.invariance_full - test.invariance_from);
          invariance(i) = surface ? 0 : math::min(1, math::max(0, full));
        } else {
          role(i) = w_fluid == 0                   ? Role::excluded
                    : p_fluid < -p_tol * w_fluid ? Role::dirichlet
                                                 : Role::wall;
          invariance(i) = 0;
        }
      });
}

}  // namespace dvisph
