#pragma once
// Structure-of-arrays storage of DEM beads (solid spheres; in 2D, spheres moving in a
// plane, so mass and inertia stay those of a sphere). `id` is the index at creation and
// survives reordering: contact history refers to partners by it.
#include "solvers/dem/rotation.hpp"
#include "src/checkpoint.hpp"

#include <string>
#include <vector>

namespace dvisph::dem {

template <int D, class Space>
struct Spheres {
  using execution_space = Space;
  using memory_space = typename Space::memory_space;
  static constexpr int dim = D;
  static constexpr int rdim = rot_dim<D>;

  int n = 0;
  Kokkos::View<Real* [D], memory_space> x, v;     // centre [m], velocity [m/s]
  Kokkos::View<Real* [rdim], memory_space> omega;  // angular velocity [rad/s]
  Kokkos::View<Real*, memory_space> radius, mass, inertia;  // [m], [kg], [kg m^2]
  Kokkos::View<int*, memory_space> id;
  // Force from outside the DEM (the fluid), held over a fluid step [N].
  Kokkos::View<Real* [D], memory_space> f_ext;
  // Sums of the contact forces and torques at the last force evaluation [N], [N m];
  // velocity Verlet needs them at the start of the next step, so they are state.
  Kokkos::View<Real* [D], memory_space> force;
  Kokkos::View<Real* [rdim], memory_space> torque;

  Spheres() = default;
  explicit Spheres(int count, const std::string& name = "spheres")
      : n(count),
        x("dvisph::" + name + "::x", count),
        v("dvisph::" + name + "::v", count),
        omega("dvisph::" + name + "::omega", count),
        radius("dvisph::" + name + "::radius", count),
        mass("dvisph::" + name + "::mass", count),
        inertia("dvisph::" + name + "::inertia", count),
        id("dvisph::" + name + "::id", count),
        f_ext("dvisph::" + name + "::f_ext", count),
        force("dvisph::" + name + "::force", count),
        torque("dvisph::" + name + "::torque", count) {}

  // Beads of one radius and density at the given centres, at rest.
  Spheres(const std::vector<Vec<D>>& centres, Real r, Real density,
          const std::string& name = "spheres")
      : Spheres(static_cast<int>(centres.size()), name) {
    auto hx = Kokkos::create_mirror_view(x);
    auto hid = Kokkos::create_mirror_view(id);
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < D; ++k) hx(i, k) = centres[i][k];
      hid(i) = i;
    }
    Kokkos::deep_copy(x, hx);
    Kokkos::deep_copy(id, hid);
    Kokkos::deep_copy(radius, r);
    set_mass_properties(density);
  }

  // Mass and moment of inertia (2/5 m r^2) of solid spheres from their radii.
  void set_mass_properties(Real density) {
    auto r = radius;
    auto m = mass;
    auto I = inertia;
    Kokkos::parallel_for(
        "dvisph::dem::spheres::mass_properties", Kokkos::RangePolicy<Space>(0, n),
        KOKKOS_LAMBDA(int i) {
          m(i) = density * 4.0 / 3.0 * math::pi * r(i) * r(i) * r(i);
          I(i) = 0.4 * m(i) * r(i) * r(i);
        });
  }

  // Calls f(name, view) on every per-bead view (for reordering and checkpoints).
  template <class F>
  void for_each_field(F&& f) {
    f("x", x);
    f("v", v);
    f("omega", omega);
    f("radius", radius);
    f("mass", mass);
    f("inertia", inertia);
    f("id", id);
    f("f_ext", f_ext);
    f("force", force);
    f("torque", torque);
  }
};

// The beads of a checkpoint written by DemSolver::save (e.g. a settled bed), with
// their velocities; forces from outside cleared.
template <int D, class Space>
Spheres<D, Space> read_spheres(const Checkpoint& c) {
  Spheres<D, Space> s(static_cast<int>(c.extents("dem/x").at(0)));
  if (c.extents("dem/x").at(1) != static_cast<std::size_t>(D))
    throw std::runtime_error("checkpoint: beads of another dimension");
  s.for_each_field([&](const char* name, auto& field) { c.get(std::string("dem/") + name, field); });
  Kokkos::deep_copy(s.f_ext, 0);
  return s;
}

}  // namespace dvisph::dem
