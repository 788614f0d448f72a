#pragma once
// Laplacian of Morris (1997) / Shao & Lo (2003):
//   <lap f>_i = sum_j (m_j/rho_j) 2 (f_i - f_j) x_ij . grad W_ij / (r_ij^2 + eta^2),
// eta^2 = 0.01 h^2. The pair weight is symmetric in i, j for equal volumes, which is
// what makes the pressure Poisson operator symmetric; laplacian_weight is the one
// place it is computed, for this operator and for the PPE.
#include "kernels/field.hpp"

namespace dvisph {

// 2 V_j x_ij . grad W_ij / (r^2 + 0.01 h^2)  (negative: x.grad W < 0)
template <int D, class Kernel>
KOKKOS_INLINE_FUNCTION Real laplacian_weight(const Kernel& kernel, Real r, Real volume_j) {
  return 2 * volume_j * kernel.dW_over_r(r) * r * r / (r * r + 0.01 * kernel.h * kernel.h);
}

template <int D, class Sweep, class Kernel, class X, class M, class Rho, class F, class Out>
void laplacian(const Sweep& sweep, const Kernel& kernel, const X& x, const M& m, const Rho& rho,
               const F& f, const Out& out, int n) {
  using Space = typename Sweep::execution_space;
  Kokkos::parallel_for(
      "dvisph::laplacian", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        const int nc = components(f);
        Real fi[max_components], sum[max_components] = {};
        for (int c = 0; c < nc; ++c) fi[c] = at(f, i, c);
        sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>&, Real r) {
          const Real w = laplacian_weight<D>(kernel, r, m(j) / rho(j));
          for (int c = 0; c < nc; ++c) sum[c] += w * (fi[c] - at(f, j, c));
        });
        for (int c = 0; c < nc; ++c) at(out, i, c) = sum[c];
      });
}

}  // namespace dvisph
