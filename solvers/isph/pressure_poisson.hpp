#pragma once
// The pressure Poisson equation (method.md eq. 5) as a symmetric positive definite
// system A P = b over the unknown particles. Eq. 5 divided by C_r rho_bar / eps
// (rho_bar = eps rho_f) reads (1/C_r) lap P = rho_f div v* / dt + gamma eps rho_f
// (1 - <rho>/rho_bar_ref) / dt^2; in a bed whose beads move, the water's continuity
// d eps/dt + div v = 0 adds d eps/dt to div v* (coupling.porosity_rate, docs/coupling.md).
// The Morris Laplacian (kernels/laplacian.hpp) with per-particle volumes V_j and the
// pair coefficient k_ij of the medium (medium.hpp), row i scaled by V_i / V_ref, gives
// A_ij = -s_i s_j k_ij L_ij (s = V / V_ref, L_ij the Laplacian weight at V_ref):
// symmetric. Clear water: s = k = 1, A = -L. The stencil holds fluid and active wall
// particles; Dirichlet particles (P = 0) add only to the diagonal.
//   fluid rows: b = -s_i rho_f ((<div v*> + d eps/dt)/dt + w gamma eps_i
//               (1 - <rho>/(eps_i rho_ref)) / dt^2), w the particle's invariance
//               weight (1 where its support is full, 0 where it reaches into the air,
//               and on the surface; roles.hpp).
//               Free surface, ghost-fluid style (Gibou et al. 2002): the part of a
//               fluid particle's support that is empty is air at P = 0 half a spacing
//               beyond the particles, i.e. twice the missing diagonal weight, so the
//               surface layer gets the pressure of its depth and the symmetric
//               gradient holds it up. It is added on every fluid row, so disordered
//               interior particles whose diagonal falls short get some too, which pulls
//               their pressure toward 0 a little; weighted by 1 - w instead
//               (`numerics.ghost_air: truncated`, air only where the support is cut)
//               a jittered tank diverged within 15 steps: the interior share also
//               stabilizes (docs/isph.md). No fluid particle is Dirichlet and no role
//               flip changes the matrix abruptly.
//   wall rows:  the wall pressure continues the fluid's, a Neumann condition: the
//               hydrostatic gradient, b = -L(P_h), P_h = rho0 g.x, plus, where the
//               water moves into the wall, the step dP/dn = rho0 vn / dt that brings
//               its normal velocity vn to rest (vn: the Shepard average over the wall
//               particle's water neighbours of v*.n beyond gravity's share, each over
//               its mobility, 1 in clear water; n from the tank's faces,
//               tank_walls.hpp). Without that step the hydrostatic continuation
//               lets a front driven into a wall go through it
//               (docs/stability.md, dam_break_2d_impact). Water moving away from a wall
//               is not pulled back: the term only pushes. Only b carries it: the
//               matrix stays symmetric.
// Several right-hand sides differ only in gamma; they share every traversal.
#include "kernels/laplacian.hpp"
#include "solvers/isph/roles.hpp"
#include "solvers/isph/tank_walls.hpp"
#include "solvers/pcg.hpp"

namespace dvisph {

template <int D, class Sweep, class Kernel, class X, class RoleV, class Medium = ClearWater>
struct PressurePoisson {
  using Space = typename Sweep::execution_space;
  Sweep sweep;
  Kernel kernel;
  X x;
  RoleV role;
  Real volume;         // V_ref, the volume of a lattice particle
  Real full_diagonal;  // sum of |Laplacian weights| over a full lattice support
  TankWalls<D> walls;
  Medium medium = {};
  bool air_everywhere = true;  // numerics.ghost_air
  bool air = true;             // false where there is no free surface (every axis periodic)

  // A_ij of a pair of unknowns or stencil particles at distance r (negative)
  KOKKOS_INLINE_FUNCTION Real coefficient(int i, int j, Real r) const {
    return medium.volume_ratio(i) * medium.volume_ratio(j) * medium.pair_coefficient(i, j) *
           laplacian_weight<D>(kernel, r, volume);
  }

  // diag(i) and b(i, k) for gamma[k], k < b.extent(1); zero on rows that are not unknowns.
  // invariance(i): the weight of the density-invariance term (density_and_roles).
  template <class VStar, class Rho, class Weight, class Diag, class B>
  void assemble(const VStar& vstar, const Rho& rho, const Weight& invariance, Real rho0,
                Real rho_ref, Vec<D> g, Real dt, const Real (&gamma)[max_rhs], const Diag& diag,
                const B& b, int n) const {
    const auto self = *this;
    const int K = static_cast<int>(b.extent(1));
    Real gam[max_rhs];
    for (int k = 0; k < max_rhs; ++k) gam[k] = gamma[k];
    Kokkos::parallel_for(
        "dvisph::pressure_poisson::assemble", RowPolicy<Space>(0, n),
        KOKKOS_LAMBDA(int i) {
          const Role ri = self.role(i);
          if (!unknown(ri)) {
            diag(i) = 0;
            for (int k = 0; k < K; ++k) b(i, k) = 0;
            return;
          }
          const Vec<D> vi = row<D>(vstar, i);
          const bool wall = ri == Role::wall;
          const Vec<D> n = wall ? self.walls.inward_normal(row<D>(self.x, i)) : Vec<D>::zero();
          Real d = 0, div = 0, wall_source = 0, approach = 0, shepard = 0, lever = 0;
          self.sweep.for_each(i, row<D>(self.x, i), [&](int j, const Vec<D>& xij, Real r) {
            const Role rj = self.role(j);
            if (!in_stencil(rj)) return;
            const Real w = self.coefficient(i, j, r);
            const Vec<D> vj = row<D>(vstar, j);
            d -= w;
            div += self.volume * self.medium.volume_ratio(j) * dot(vj - vi, self.kernel.grad(xij, r));
            wall_source += w * dot(g, xij);
            if (wall && water(rj)) {
              const Real W = self.kernel.W(r), mob = self.medium.mobility(j);
              // v*_j.n beyond gravity's share (the predictor's, drag included), over the
              // mobility: the pressure step that stops it is (rho0 / dt) vn / mob, since
              // water in a bed takes only mob of a pressure gradient
              approach += W * ((dot(vj, n) - dt * (mob * dot(g, n))) / mob);
              shepard += W;
              lever += w * dot(n, xij);
            }
          });
          // the water's mean normal velocity at the wall (beyond gravity's), where it
          // moves into the wall: dP/dn = rho0 vn / (dt mob) brings it to rest
          if (shepard > 0) wall_source += math::min(0, approach / shepard) / dt * lever;
          const Real si = self.medium.volume_ratio(i), eps = self.medium.porosity(i);
          if constexpr (is_porous<Medium>) div += self.medium.porosity_rate(i);
          const Real air_share = wall || !self.air ? 0 : self.air_everywhere ? 1 : 1 - invariance(i);
          // a full support's diagonal at this particle's mobility: a bed's lower mobility
          // is not a missing support
          const Real full = si * self.full_diagonal * self.medium.mobility(i);
          const Real air = air_share * 2 * math::max(0, full - d);
          diag(i) = d + air;
          for (int k = 0; k < K; ++k) {
            if (wall) b(i, k) = -rho0 * wall_source;
            else b(i, k) = si * (-rho0 / dt * div - invariance(i) * gam[k] * eps * rho0 *
                                                        (1 - rho(i) / (eps * rho_ref)) / (dt * dt));
          }
        });
  }

  // f(j, A_ij) for each off-diagonal coefficient of row i (none on rows that are not
  // unknowns); the one definition of the matrix, for apply and for PoissonMatrix.
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each_coefficient(int i, F&& f) const {
    if (!unknown(role(i))) return;
    sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>&, Real r) {
      if (unknown(role(j)) && j != i) f(j, coefficient(i, j, r));
    });
  }

  // Warm start: p keeps the last step's values on the unknowns, zero elsewhere.
  template <class P>
  void warm_start(const P& p, int n) const {
    const auto r = role;
    const int K = static_cast<int>(p.extent(1));
    Kokkos::parallel_for(
        "dvisph::pressure_poisson::warm_start", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          if (!unknown(r(i)))
            for (int k = 0; k < K; ++k) p(i, k) = 0;
        });
  }

  // q = A p for all columns (diag is zero on rows that are not unknowns).
  template <class P, class Diag>
  void apply(const P& p, const P& q, const Diag& diag, int n) const {
    const auto self = *this;
    const int K = static_cast<int>(p.extent(1));
    Kokkos::parallel_for(
        "dvisph::pressure_poisson::apply", RowPolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          Real sum[max_rhs] = {};
          self.for_each_coefficient(i, [&](int j, Real w) {
            for (int k = 0; k < K; ++k) sum[k] += w * p(j, k);
          });
          for (int k = 0; k < K; ++k) q(i, k) = sum[k] + diag(i) * p(i, k);
        });
  }
};

// Every axis periodic (no wall, no free surface, no air): the matrix annihilates the
// constants, so CG converges only on a right-hand side orthogonal to them. The mean of b
// over the unknowns (diag > 0) is removed from each column; the pressure is then defined
// up to a constant, which no gradient sees.
template <class Space, class B, class Diag>
void remove_mean(const B& b, const Diag& diag, int n) {
  const int K = static_cast<int>(b.extent(1));
  Sums<max_rhs + 1> sums;  // the columns' sums, then the count of unknowns
  Kokkos::parallel_reduce(
      "dvisph::pressure_poisson::rhs_mean", Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i, Sums<max_rhs + 1>& s) {
        if (!(diag(i) > 0)) return;
        for (int k = 0; k < K; ++k) s.v[k] += b(i, k);
        s.v[max_rhs] += 1;
      },
      sums);
  if (!(sums.v[max_rhs] > 0)) return;
  ColumnSums mean;
  for (int k = 0; k < K; ++k) mean.v[k] = sums.v[k] / sums.v[max_rhs];
  Kokkos::parallel_for(
      "dvisph::pressure_poisson::remove_rhs_mean", Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i) {
        if (diag(i) > 0)
          for (int k = 0; k < K; ++k) b(i, k) -= mean.v[k];
      });
}

}  // namespace dvisph
