#pragma once
// What a full support looks like: the interior values of the initial lattice
// (spacing dx, particle volume dx^D, density rho0), the references of the density
// error and the density-invariance term, of the free-surface tests and of the ghost
// air (pressure_poisson.hpp).
#include "kernels/laplacian.hpp"
#include "solvers/isph/roles.hpp"
#include "src/scene.hpp"

#include <cmath>
#include <functional>

namespace dvisph {

template <int D>
struct SupportReference {
  Real rho = 0;        // summation density
  Real div_r = 0;      // position divergence
  Real laplacian = 0;  // sum of |Laplacian weights|: the diagonal of a full row of A
  Real face_gradient = 0;  // |sum_j V grad W_ij| for a particle on the face of a half-space
};

template <int D, class Kernel>
SupportReference<D> support_reference(const Kernel& kernel, Real dx, Real rho0) {
  const Real volume = std::pow(dx, D);
  const int reach = static_cast<int>(std::ceil(kernel.radius() / dx)) + 1;
  SupportReference<D> ref;
  int c[3] = {0, 0, 0};
  Real face = 0;  // the normal component (the others cancel by symmetry)
  std::function<void(int)> loop = [&](int axis) {
    if (axis == D) {
      Real r2 = 0;
      for (int k = 0; k < D; ++k) r2 += c[k] * dx * c[k] * dx;
      const Real r = std::sqrt(r2);
      ref.rho += rho0 * volume * kernel.W(r);
      ref.div_r -= volume * kernel.dW_over_r(r) * r2;
      if (r > 0) ref.laplacian -= laplacian_weight<D>(kernel, r, volume);
      // neighbours at or below the particle's level (x_ij = -c dx): the half-space
      if (c[D - 1] <= 0) face -= volume * kernel.dW_over_r(r) * c[D - 1] * dx;
      return;
    }
    for (c[axis] = -reach; c[axis] <= reach; ++c[axis]) loop(axis + 1);
  };
  loop(0);
  ref.face_gradient = std::abs(face);
  return ref;
}

// The scene's free-surface and invariance-weight choices with the lattice references.
template <int D>
SurfaceTest<D> surface_test(const Scene& s, const SupportReference<D>& ref) {
  Vec<D> g;
  for (int k = 0; k < D; ++k) g[k] = s.gravity[k];
  return {s.surface_criterion == "density", s.surface_density_threshold,
          s.surface_divergence_threshold, s.invariance_truncation[0], s.invariance_truncation[1],
          ref.rho, ref.div_r, ref.face_gradient, s.density, g};
}

}  // namespace dvisph
