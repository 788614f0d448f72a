#pragma once
// What a full support looks like: the interior values of the initial lattice
// (spacing dx, particle volume dx^D, density rho0), the references of the density
// error and the density-invariance term, of the free-surface tests and of the ghost
// air (pressure_poisson.hpp).
#include "kernels/laplacian.hpp"

#include <cmath>
#include <functional>

namespace dvisph {

template <int D>
struct SupportReference {
  Real rho = 0;        // summation density
  Real div_r = 0;      // position divergence
  Real laplacian = 0;  // sum of |Laplacian weights|: the diagonal of a full row of A
};

template <int D, class Kernel>
SupportReference<D> support_reference(const Kernel& kernel, Real dx, Real rho0) {
  const Real volume = std::pow(dx, D);
  const int reach = static_cast<int>(std::ceil(kernel.radius() / dx)) + 1;
  SupportReference<D> ref;
  int c[3] = {0, 0, 0};
  std::function<void(int)> loop = [&](int axis) {
    if (axis == D) {
      Real r2 = 0;
      for (int k = 0; k < D; ++k) r2 += c[k] * dx * c[k] * dx;
      const Real r = std::sqrt(r2);
      ref.rho += rho0 * volume * kernel.W(r);
      ref.div_r -= volume * kernel.dW_over_r(r) * r2;
      if (r > 0) ref.laplacian -= laplacian_weight<D>(kernel, r, volume);
      return;
    }
    for (c[axis] = -reach; c[axis] <= reach; ++c[axis]) loop(axis + 1);
  };
  loop(0);
  return ref;
}

}  // namespace dvisph
