#pragma once
// Symmetric gradient  <grad f>_i = rho_i sum_j m_j (f_i/rho_i^2 + f_j/rho_j^2) grad W_ij.
// Antisymmetric pair forces: used for pressure, it conserves linear momentum.
// f may have several columns (out is then n x (D * columns), column-major by field).
#include "kernels/field.hpp"

namespace dvisph {

template <int D, class Sweep, class Kernel, class X, class M, class Rho, class F, class Out>
void symmetric_gradient(const Sweep& sweep, const Kernel& kernel, const X& x, const M& m,
                        const Rho& rho, const F& f, const Out& out, int n) {
  using Space = typename Sweep::execution_space;
  Kokkos::parallel_for(
      "dvisph::symmetric_gradient", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        const int nc = components(f);
        const Real inv_rho2_i = 1 / (rho(i) * rho(i));
        Real fi[max_components];
        Real sum[max_components][D] = {};
        for (int c = 0; c < nc; ++c) fi[c] = at(f, i, c) * inv_rho2_i;
        sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>& xij, Real r) {
          const Vec<D> g = kernel.grad(xij, r);
          const Real mj_rho2_j = m(j) / (rho(j) * rho(j));
          for (int c = 0; c < nc; ++c) {
            const Real s = m(j) * fi[c] + mj_rho2_j * at(f, j, c);
            for (int k = 0; k < D; ++k) sum[c][k] += s * g[k];
          }
        });
        for (int c = 0; c < nc; ++c)
          for (int k = 0; k < D; ++k) out(i, c * D + k) = rho(i) * sum[c][k];
      });
}

}  // namespace dvisph
