#pragma once
// The contacts of a bead with the walls near it (PairContacts::near_walls, set at each
// list build): the law against a plane (m* = the bead's mass), the history kept per
// bead and wall. Most beads are near no wall.
#include "solvers/dem/contact_kinematics.hpp"
#include "solvers/dem/linear_spring_dashpot.hpp"
#include "solvers/dem/pair_contacts.hpp"
#include "solvers/dem/plane_wall.hpp"

namespace dvisph::dem {

template <int D, class Space>
struct WallContacts {
  using memory_space = typename Space::memory_space;
  static constexpr int R = rot_dim<D>;

  ContactKinematics<D, Space> kin;
  PairContacts<D, Space> pairs;
  Kokkos::View<const PlaneWall<D>*, memory_space> walls;
  Kokkos::View<const Real*, memory_space> mass;
  LinearSpringDashpot<D> law;
  Kokkos::View<int*, memory_space> status;
  int walls_count, deep_flag;
  Real skin, max_overlap, dt;

  // Adds the walls' force and torque on i to fi and ti; returns how many touch.
  KOKKOS_INLINE_FUNCTION int operator()(int i, Vec<D>& fi, Rot<D>& ti) const {
    const unsigned near = pairs.near_walls(i);
    if (near == 0) return 0;
    const Real ri = kin.radius(i);
    const Vec<D> xi = kin.x(i), vi = kin.v(i), vai = kin.v_ahead(i);
    const Rot<D> wi = kin.omega(i), wai = kin.omega_ahead(i);
    int count = 0;
    for (int w = 0; w < walls_count; ++w) {
      if (!(near >> w & 1u)) continue;
      const PlaneWall<D> wall = walls(w);
      const bool touched = pairs.wall_touching(i, w);
      const Vec<D> xi_old = touched ? pairs.wall(i, w) : Vec<D>::zero();
      if (touched) {  // until it is found touching again below (a removed gate: never)
        pairs.wall_touching(i, w) = 0;
        pairs.set_wall(i, w, Vec<D>::zero());
      }
      if (!wall.active) continue;
      // walls beyond the search skin are skipped, as listed pairs are
      const Real gap = wall.distance(xi) - ri;
      if (gap > skin) continue;
      const Vec<D>& nrm = wall.normal;
      const Overlaps d = Overlaps::along(-gap, dot(vi, nrm), dot(vai, nrm), dt);
      if (!d.touching()) continue;
      if (d.now > max_overlap * ri) Kokkos::atomic_fetch_max(&status(deep_flag), i + 1);
      const Contact<D> c{d, nrm, vi - cross(ri * wi, nrm), vai - cross(ri * wai, nrm), math::sqrt(mass(i))};
      const ContactResponse<D> res = law(c, xi_old, dt);
      fi += res.force;
      ti += (-ri) * cross(nrm, res.force);
      pairs.set_wall(i, w, res.xi);
      pairs.wall_touching(i, w) = 1;
      ++count;
    }
    return count;
  }
};

}  // namespace dvisph::dem
