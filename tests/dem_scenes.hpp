#pragma once
// Small DEM scenes with known answers, shared by tests/tst_dem.cpp and the cross-backend
// test: the paper's glass beads (method.md §3, §5).
#include "solvers/dem/dem_solver.hpp"

#include <vector>

namespace dvisph::testing {

constexpr Real bead_d = 2.7e-3, bead_rho = 2500, bead_kn = 1000;

template <int D>
Vec<D> vec(Real a, Real b, Real c = 0) {
  Vec<D> v;
  v[0] = a;
  v[1] = b;
  if constexpr (D == 3) v[2] = c;
  return v;
}

// Host copy of a per-bead field (n, or n x C), rows ordered by bead id.
template <class View, class Ids>
std::vector<std::vector<Real>> by_id(const View& field, const Ids& id) {
  constexpr bool scalar = int(View::traits::rank) == 1;
  const auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), field);
  const auto hid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), id);
  const std::size_t ncols = scalar ? 1 : h.extent(1);
  std::vector<std::vector<Real>> rows(h.extent(0), std::vector<Real>(ncols));
  for (std::size_t i = 0; i < h.extent(0); ++i)
    for (std::size_t c = 0; c < ncols; ++c) {
      if constexpr (scalar) {
        rows[hid(i)][c] = h(i);
      } else {
        rows[hid(i)][c] = h(i, c);
      }
    }
  return rows;
}

// Two unequal beads (d and 1.5 d, 0.8 and -0.3 m/s) collide obliquely in 3D without
// gravity, with friction and rotation; returns, by bead, m, x, v and omega after they
// separate.
template <class Space>
std::vector<std::vector<Real>> two_bead_collision() {
  using namespace dem;
  const Real r = 0.5 * bead_d;
  Spheres<3, Space> s({vec<3>(-2 * r, 0, 0), vec<3>(0.5 * r, 0.4 * r, 0.1 * r)}, r, bead_rho);
  Kokkos::deep_copy(Kokkos::subview(s.radius, 1), 1.5 * r);
  s.set_mass_properties(bead_rho);
  auto hv = Kokkos::create_mirror_view(s.v);
  hv(0, 0) = 0.8;
  hv(1, 0) = -0.3;
  hv(1, 2) = 0.05;
  Kokkos::deep_copy(s.v, hv);
  LinearSpringDashpot<3> law(bead_kn, 0.7, 0.2);
  DemSolver<3, Space> dem(s, {}, law, vec<3>(-0.02, -0.02, -0.02), vec<3>(0.02, 0.02, 0.02),
                          Vec<3>::zero());
  for (int step = 0; step < 300; ++step) dem.step(dem.time_step());
  const auto m = by_id(s.mass, s.id), x = by_id(s.x, s.id), v = by_id(s.v, s.id),
             w = by_id(s.omega, s.id);
  std::vector<std::vector<Real>> out(s.n);
  for (int i = 0; i < s.n; ++i)
    for (const auto* part : {&m[i], &x[i], &v[i], &w[i]})
      out[i].insert(out[i].end(), part->begin(), part->end());
  return out;
}

}  // namespace dvisph::testing
