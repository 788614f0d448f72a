#pragma once
// <div v>_i = sum_j (m_j / rho_i) (v_j - v_i) . grad W_ij   (exact for constant v)
#include "src/core/types.hpp"

namespace dvisph {

template <int D, class Sweep, class Kernel, class X, class M, class Rho, class V, class Out>
void divergence(const Sweep& sweep, const Kernel& kernel, const X& x, const M& m, const Rho& rho,
                const V& v, const Out& out, int n) {
  using Space = typename Sweep::execution_space;
  Kokkos::parallel_for(
      "dvisph::divergence", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        const Vec<D> vi = row<D>(v, i);
        Real sum = 0;
        sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>& xij, Real r) {
          sum += m(j) * dot(row<D>(v, j) - vi, kernel.grad(xij, r));
        });
        out(i) = sum / rho(i);
      });
}

}  // namespace dvisph
