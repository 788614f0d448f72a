#pragma once
// An infinite plane that beads touch with the contact law (m* = m of the bead). A tank
// is a set of planes; a gate is a plane removed at a given time. Planes are infinite, so
// a tank's planes must not cut through the region where beads live.
#include "src/core/types.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace dvisph::dem {

template <int D>
struct PlaneWall {
  Vec<D> point;   // any point of the plane [m]
  Vec<D> normal;  // unit, pointing into the domain
  bool active;
  Real remove_at;  // time the wall goes away [s]

  PlaneWall() = default;  // trivial, so device arrays of walls need no constructor
  PlaneWall(const Vec<D>& p, const Vec<D>& n,
            Real removal_time = std::numeric_limits<Real>::infinity())
      : point(p), normal(n), active(true), remove_at(removal_time) {
    const Real len = std::sqrt(dot(n, n));
    if (!(len > 0)) throw std::invalid_argument("PlaneWall: zero normal");
    normal = (1 / len) * n;
  }

  // Signed distance of x from the plane, positive inside the domain.
  KOKKOS_INLINE_FUNCTION Real distance(const Vec<D>& x) const { return dot(x - point, normal); }
};

// The walls of an axis-aligned box [lo, hi] (4 in 2D, 6 in 3D), normals inward.
template <int D>
std::vector<PlaneWall<D>> box_walls(const Vec<D>& lo, const Vec<D>& hi) {
  std::vector<PlaneWall<D>> walls;
  for (int k = 0; k < D; ++k) {
    Vec<D> n = Vec<D>::zero();
    n[k] = 1;
    walls.emplace_back(lo, n);
    n[k] = -1;
    walls.emplace_back(hi, n);
  }
  return walls;
}

}  // namespace dvisph::dem
