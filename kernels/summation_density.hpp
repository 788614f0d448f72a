#pragma once
// <rho_i> = sum_j m_j W_ij
#include "src/core/types.hpp"

namespace dvisph {

template <int D, class Sweep, class Kernel, class X, class M, class Out>
void summation_density(const Sweep& sweep, const Kernel& kernel, const X& x, const M& m,
                       const Out& rho, int n) {
  using Space = typename Sweep::execution_space;
  Kokkos::parallel_for(
      "dvisph::summation_density", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        Real sum = 0;
        sweep.for_each(i, row<D>(x, i), [&](int j, const Vec<D>&, Real r) { sum += m(j) * kernel.W(r); });
        rho(i) = sum;
      });
}

}  // namespace dvisph
