#pragma once
// A coupled scene for tests: a ball of water falling freely (no wall within reach) with
// beads moving through it; and its state after a few steps on a given backend.
#include "kernels/wendland_c2.hpp"
#include "solvers/isph/isph_solver.hpp"
#include "src/scene.hpp"
#include "src/scene_beads.hpp"

#include <vector>

namespace dvisph::testing {

inline const char* coupled_blob = R"(
name: blob
dimension: 3
end_time: 1
material: {kinematic_viscosity: 1.0e-6}
geometry:
  spacing: 0.002
  tank: {lo: [0, 0, 0], hi: [0.05, 0.05, 0.05]}
  fluid: [{lo: [0.015, 0.015, 0.015], hi: [0.035, 0.035, 0.035]}]
solids:
  diameter: 0.0027
  beads:
    - {position: [0.025, 0.025, 0.025], velocity: [0.1, 0, -0.2]}
    - {position: [0.0255, 0.022, 0.0285], velocity: [0, 0.05, 0]}
    - {position: [0.02, 0.028, 0.02], velocity: [-0.1, 0.1, 0.3]}
numerics: {reorder_every: 0, dt_max: 5.0e-4}
)";

// a host copy that is a copy also where the view already lives on the host
template <class V>
auto snapshot_of(const V& v) {
  auto h = Kokkos::create_mirror(Kokkos::HostSpace(), v);
  Kokkos::deep_copy(h, v);
  return h;
}

// Fluid positions and velocities, then bead positions and velocities, after `steps`.
template <class Space>
std::vector<double> coupled_blob_state(int steps) {
  const Scene s = parse_scene(coupled_blob);
  auto beads = scene_dem<3, Space>(s);
  IsphSolver<3, WendlandC2<3>, Space, PorousMedium<3, Space>> solver(s, &beads);
  for (int k = 0; k < steps; ++k) solver.step();
  std::vector<double> out;
  for (const auto& v : {snapshot_of(solver.particles().x), snapshot_of(solver.particles().v),
                        snapshot_of(beads.spheres().x), snapshot_of(beads.spheres().v)})
    for (std::size_t i = 0; i < v.extent(0); ++i)
      for (int k = 0; k < 3; ++k) out.push_back(v(i, k));
  return out;
}

}  // namespace dvisph::testing
