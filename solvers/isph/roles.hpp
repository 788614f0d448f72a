#pragma once
// Summation density, the role of each particle in the pressure solve, and how much of
// each fluid particle's support is cut off by a free surface:
//  - fluid particles are unknowns; those on the free surface are marked `surface`.
//    The surface test (a scene choice) is the position divergence
//    div r = sum_j V_j (x_j - x_i).grad W_ij (Lee et al. 2008), which measures how much
//    of the support is empty, or the summation density;
//  - truncation t_i = |sum_j V_j grad W_ij| / g_face, with g_face the same sum on the
//    face of a flat half-space lattice: 0 in a full support, whatever the spacing (the
//    sum is a gradient of a constant: uniform expansion, compression and a porous bed
//    with V_j = m_j / (eps_j rho_f) leave it at 0), 1 on a flat face, 0.18 (2D) and
//    0.16 (3D) one layer below it at h = 1.5 dx, 0 two layers below; it scatters on
//    disordered particles (0.1 dx jitter: 0.09 median, 0.25 at most in 2D;
//    figures from scripts/ppe_symbols.py). The metric's free-surface test reads it
//    (src/metrics.hpp);
//  - the weight of the density-invariance term: 1 up to t = `invariance_full`, 0 from
//    `invariance_none`, linear in between, and 0 on the surface. Where part of the
//    support is air, <rho> is low because of the air, not because the water expanded;
//    t tells the two apart where <rho> and div r cannot (docs/isph.md has the choice
//    and the old div r weight it replaces, which switched the term off in expanded
//    water);
//  - wall particles with no fluid neighbour play no part (excluded);
//  - a wall particle to which the water pressure, continued hydrostatically from its
//    fluid neighbours (Shepard average of P_j + rho0 g.(x_w - x_j), last step's P),
//    would be negative lies beside the free surface: Dirichlet P = 0, so that it does
//    not pull the water up the wall; the others are unknowns.
#include "solvers/isph/medium.hpp"
#include "src/core/types.hpp"

namespace dvisph {

enum class Role : std::uint8_t { excluded = 0, dirichlet = 1, fluid = 2, surface = 3, wall = 4 };

KOKKOS_INLINE_FUNCTION bool in_stencil(Role r) { return r != Role::excluded; }
KOKKOS_INLINE_FUNCTION bool unknown(Role r) { return r >= Role::fluid; }
KOKKOS_INLINE_FUNCTION bool water(Role r) { return r == Role::fluid || r == Role::surface; }

// Whether particle i is water or a wall particle in the water's stencil.
template <class RoleV>
struct WetParticle {
  RoleV role;
  KOKKOS_INLINE_FUNCTION bool operator()(int i) const { return in_stencil(role(i)); }
};

template <int D>
struct SurfaceTest {
  bool by_density;  // else by position divergence
  Real density_threshold, divergence_threshold;  // fractions of the interior values
  Real invariance_full, invariance_none;         // truncations: weight 1 up to, 0 from
  Real rho_ref, div_r_ref;                       // interior values of <rho> and div r
  Real face_gradient;                            // |sum_j V_j grad W_ij| on a flat face
  Real rho0;
  Vec<D> g;
};

template <int D, class Sweep, class Kernel, class X, class M, class KindV, class P, class Medium,
          class Rho, class RoleV, class Weight, class Truncation>
void density_and_roles(const Sweep& sweep, const Kernel& kernel, const X& x, const M& m,
                       const KindV& kind, const P& p_last, const Medium& medium, Real volume,
                       SurfaceTest<D> test, const Rho& rho, const RoleV& role,
                       const Weight& invariance, const Truncation& truncation, int n) {
  using Space = typename Sweep::execution_space;
  // tolerance on the continued pressure: round-off of symmetric sums
  Real gnorm = 0;
  for (int k = 0; k < D; ++k) gnorm += test.g[k] * test.g[k];
  const Real p_tol = 1e-9 * test.rho0 * math::sqrt(gnorm) * kernel.h;
  Kokkos::parallel_for(
      "dvisph::isph::density_and_roles", RowPolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        const bool fluid = kind(i) == Kind::fluid;
        Real sum = 0, div_r = 0, w_fluid = 0, p_fluid = 0;
        Vec<D> cut = Vec<D>::zero();
        sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>& xij, Real r) {
          const Real w = kernel.W(r), vj = volume * medium.volume_ratio(j);
          // eps_i rho_f sum_j V_j W_ij, V_j = m_j / (eps_j rho_f): the summation density
          // where each neighbour counts at its own porosity (summing m_j W_ij would
          // smooth eps twice and read a bed's edge as 10 % off); a wall continues the
          // water beside it, V_j = V_ref
          sum += (kind(j) == Kind::fluid ? m(j) / medium.porosity(j) : m(j)) * w;
          div_r -= vj * kernel.dW_over_r(r) * r * r;
          cut += vj * kernel.grad(xij, r);
          if (!fluid && kind(j) == Kind::fluid) {
            w_fluid += w;
            p_fluid += w * (p_last(j, 0) + test.rho0 * dot(test.g, xij));
          }
        });
        rho(i) = medium.porosity(i) * sum;
        if (fluid) {
          const bool surface = test.by_density ? sum < test.density_threshold * test.rho_ref
                                               : div_r < test.divergence_threshold * test.div_r_ref;
          role(i) = surface ? Role::surface : Role::fluid;
          const Real t = math::sqrt(dot(cut, cut)) / test.face_gradient;
          const Real full = (test.invariance_none - t) / (test.invariance_none - test.invariance_full);
          invariance(i) = surface ? 0 : math::min(1, math::max(0, full));
          truncation(i) = t;
        } else {
          role(i) = w_fluid == 0                   ? Role::excluded
                    : p_fluid < -p_tol * w_fluid ? Role::dirichlet
                                                 : Role::wall;
          invariance(i) = 0;
          truncation(i) = 0;
        }
      });
}

}  // namespace dvisph
