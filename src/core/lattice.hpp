#pragma once
// Host-side generation of lattice points (setup only, never in the time step).
#include "src/core/lattice_sites.hpp"
#include "src/core/types.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace dvisph {

// Points at lo + (i + 1/2) dx filling the box [lo, hi), each optionally displaced
// by a uniform random offset in [-jitter, jitter] per axis (reproducible by seed).
template <int D>
std::vector<Vec<D>> lattice(const Vec<D>& lo, const Vec<D>& hi, Real dx, Real jitter = 0,
                            unsigned seed = 1) {
  int count[3] = {1, 1, 1};
  long total = 1;
  for (int k = 0; k < D; ++k) {
    count[k] = static_cast<int>(lattice_sites(hi[k] - lo[k], dx));
    total *= count[k];
  }
  std::vector<Vec<D>> points;
  points.reserve(total);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> offset(-jitter, jitter);
  for (int c2 = 0; c2 < count[2]; ++c2)
    for (int c1 = 0; c1 < count[1]; ++c1)
      for (int c0 = 0; c0 < count[0]; ++c0) {
        const int c[3] = {c0, c1, c2};
        Vec<D> p;
        for (int k = 0; k < D; ++k) p[k] = lo[k] + (c[k] + 0.5) * dx;
        if (jitter > 0)
          for (int k = 0; k < D; ++k) p[k] += offset(rng);
        points.push_back(p);
      }
  return points;
}

// Copies host points into an (n x D) device view.
template <int D, class XView>
void copy_points(const std::vector<Vec<D>>& points, const XView& x) {
  auto h = Kokkos::create_mirror_view(x);
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < D; ++k) h(i, k) = points[i][k];
  Kokkos::deep_copy(x, h);
}

}  // namespace dvisph
