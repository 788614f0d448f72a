#pragma once
// Velocity correction v = v* - dt (eps/C_r) (1/rho_f) grad P (method.md §4; the fluid's
// share of the pressure gradient is eps grad P, medium.hpp) with the symmetric gradient
// grad P_i = sum_j V_j (P_i + P_j) grad W_ij (pair forces V_i V_j (P_i + P_j) grad W_ij,
// equal and opposite), V_j = s_j V_ref from the medium (medium.hpp). Column `physical`
// of P gives the velocity carried forward; column `transport` the velocity that moves
// the particles (the same column when alpha = beta; then vt may alias v).
#include "solvers/isph/roles.hpp"

namespace dvisph {

template <int D, class Sweep, class Kernel, class X, class VStar, class P, class KindV, class RoleV,
          class Medium, class V>
void corrector(const Sweep& sweep, const Kernel& kernel, const X& x, const VStar& vstar, const P& p,
               const KindV& kind, const RoleV& role, const Medium& medium, Real rho0, Real volume,
               Real dt, int physical, int transport, const V& v, const V& vt, int n) {
  using Space = typename Sweep::execution_space;
  Kokkos::parallel_for(
      "dvisph::isph::corrector", RowPolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        if (kind(i) != Kind::fluid) return;
        const Real pa = p(i, physical), pb = p(i, transport);
        Vec<D> ga = Vec<D>::zero(), gb = Vec<D>::zero();
        sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>& xij, Real r) {
          if (!in_stencil(role(j))) return;
          const Vec<D> gw = kernel.grad(xij, r);
          const Real sj = medium.volume_ratio(j);
          for (int k = 0; k < D; ++k) {
            ga[k] += sj * (pa + p(j, physical)) * gw[k];
            gb[k] += sj * (pb + p(j, transport)) * gw[k];
          }
        });
        Vec<D> grad;
        for (int k = 0; k < D; ++k) grad[k] = volume * ga[k];
        const Real s = dt * volume / rho0 * medium.mobility(i);
        Vec<D> vi;
        for (int k = 0; k < D; ++k) {
          vt(i, k) = vstar(i, k) - s * gb[k];
          v(i, k) = vi[k] = vstar(i, k) - s * ga[k];
        }
        medium.keep_corrected(i, grad, vi);
      });
}

// What the move found: the fastest particle by its physical velocity (the CFL limit),
// the largest |v_transport - v|, and the first particle (by index) that left the domain
// or got a non-finite value (-1: none).
struct MoveReport {
  Real max_speed = 0;
  Real max_transport_difference = 0;
  int bad = -1;
};

// x += dt vt / eps for fluid particles (the particles carry the superficial velocity
// eps u_f; eps from the medium), v the physical velocity (vt may be v); reports the
// largest speed u_f, the largest |vt - v| / eps and any particle that is not finite or
// outside [lo, hi]. (A functor with its own join: Kokkos 3.x has no multiple-reducer
// parallel_reduce.)
template <int D, class Space, class X, class V, class KindV, class Medium>
struct MoveParticles {
  struct value_type {
    Real max_speed2, max_difference2;
    int first_bad;
  };
  X x;
  V v, vt;
  KindV kind;
  Medium medium;
  Real dt;
  Vec<D> lo, hi;
  Periodic<D> periodic;  // positions wrap along periodic axes
  int n;

  KOKKOS_INLINE_FUNCTION void init(value_type& r) const { r = {0, 0, n}; }
  KOKKOS_INLINE_FUNCTION void join(value_type& a, const value_type& b) const {
    if (b.max_speed2 > a.max_speed2) a.max_speed2 = b.max_speed2;
    if (b.max_difference2 > a.max_difference2) a.max_difference2 = b.max_difference2;
    if (b.first_bad < a.first_bad) a.first_bad = b.first_bad;
  }
  KOKKOS_INLINE_FUNCTION void join(volatile value_type& a, const volatile value_type& b) const {
    if (b.max_speed2 > a.max_speed2) a.max_speed2 = b.max_speed2;
    if (b.max_difference2 > a.max_difference2) a.max_difference2 = b.max_difference2;
    if (b.first_bad < a.first_bad) a.first_bad = b.first_bad;
  }
  KOKKOS_INLINE_FUNCTION void operator()(int i, value_type& r) const {
    if (kind(i) != Kind::fluid) return;
    Real v2 = 0, d2 = 0;
    bool ok = true;
    const Real eps = medium.porosity(i);
    for (int k = 0; k < D; ++k) {
      const Real u = v(i, k) / eps, ut = vt(i, k) / eps;
      x(i, k) = periodic.wrap(x(i, k) + dt * ut, k);
      v2 += u * u;
      d2 += (ut - u) * (ut - u);
      ok = ok && math::isfinite(x(i, k)) && x(i, k) >= lo[k] && x(i, k) <= hi[k];
    }
    ok = ok && math::isfinite(v2) && math::isfinite(d2);
    if (v2 > r.max_speed2) r.max_speed2 = v2;
    if (d2 > r.max_difference2) r.max_difference2 = d2;
    if (!ok && i < r.first_bad) r.first_bad = i;
  }

  MoveReport run() const {
    value_type r;
    Kokkos::parallel_reduce("dvisph::isph::move", Kokkos::RangePolicy<Space>(0, n), *this, r);
    return {std::sqrt(r.max_speed2), std::sqrt(r.max_difference2), r.first_bad < n ? r.first_bad : -1};
  }
};

}  // namespace dvisph
