#pragma once
// Predictor v* = v + dt (eps/C_r) (g + nu lap v + F_r) for fluid particles (method.md §4;
// eps, C_r, the volumes of the viscous sum and the drag F_r, implicit, from the medium,
// medium.hpp). Wall particles get
// v* = dt (eps/C_r) g (eps, C_r of the bed beside them): with the wall rows of the PPE (pressure_poisson.hpp) this is the
// discrete form of the Neumann condition dP/dn = rho g.n, under which still water
// is an exact steady state.
#include "kernels/laplacian.hpp"

namespace dvisph {

// nu = 0: no neighbour loop at all. `no_slip`: walls enter the viscous sum with v = 0.
template <int D, class Sweep, class Kernel, class X, class V, class KindV, class Medium, class VStar>
void predictor(const Sweep& sweep, const Kernel& kernel, const X& x, const V& v, const KindV& kind,
               const Medium& medium, Vec<D> g, Real nu, bool no_slip, Real volume, Real dt,
               const VStar& vstar, int n) {
  using Space = typename Sweep::execution_space;
  if (nu == 0) {
    Kokkos::parallel_for(
        "dvisph::isph::predictor", RowPolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          const Real f = medium.porosity(i) * medium.inverse_virtual_mass(i);
          if (kind(i) != Kind::fluid) {
            for (int k = 0; k < D; ++k) vstar(i, k) = dt * (f * g[k]);
            return;
          }
          Vec<D> a;
          for (int k = 0; k < D; ++k) a[k] = f * g[k];
          const Vec<D> vs = medium.predict(i, row<D>(v, i), a, dt);
          for (int k = 0; k < D; ++k) vstar(i, k) = vs[k];
        });
    return;
  }
  Kokkos::parallel_for(
      "dvisph::isph::predictor_viscous", RowPolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        if (kind(i) != Kind::fluid) {
          const Real f = medium.porosity(i) * medium.inverse_virtual_mass(i);
          for (int k = 0; k < D; ++k) vstar(i, k) = dt * (f * g[k]);
          return;
        }
        const Vec<D> vi = row<D>(v, i);
        Vec<D> lap = Vec<D>::zero();
        sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>&, Real r) {
          const bool wall = kind(j) != Kind::fluid;
          if (wall && !no_slip) return;
          const Real w = laplacian_weight<D>(kernel, r, volume * medium.volume_ratio(j));
          for (int k = 0; k < D; ++k) lap[k] += w * (vi[k] - (wall ? 0 : v(j, k)));
        });
        const Real f = medium.porosity(i) * medium.inverse_virtual_mass(i);
        Vec<D> a;
        // nu_E = nu / eps (Shao 2010): the pair forces m_i m_j nu L_ij (v_i - v_j) /
        // (eps_i eps_j rho_f) are then equal and opposite, so viscosity moves no momentum
        // between a bed and clear water
        const Real eps = medium.porosity(i);
        for (int k = 0; k < D; ++k) a[k] = f * (g[k] + nu * lap[k] / eps);
        const Vec<D> vs = medium.predict(i, vi, a, dt);
        for (int k = 0; k < D; ++k) vstar(i, k) = vs[k];
      });
}

}  // namespace dvisph
