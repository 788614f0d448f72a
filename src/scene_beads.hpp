#pragma once
// The DEM side of a scene (setup only): beads from lattice boxes, single beads or a
// saved bed; the tank's faces and the gate as planes; the contact law.
#include "solvers/dem/dem_solver.hpp"
#include "src/core/lattice.hpp"
#include "src/scene.hpp"
#include "src/scene_particles.hpp"

#include <fmt/format.h>

#include <vector>

namespace dvisph {

template <int D>
struct SceneBeads {
  std::vector<Vec<D>> x, v;
};

// Bead centres and velocities of the lattice boxes (bottom layer first, up to
// solids.count, which parse_scene checks the boxes hold) and the single beads.
template <int D>
SceneBeads<D> scene_beads(const Scene& s) {
  const auto& b = *s.solids;
  SceneBeads<D> out;
  std::vector<Vec<D>> sites;
  for (const auto& box : b.lattice) {
    const auto pts = lattice<D>(to_vec<D>(box.lo), to_vec<D>(box.hi), b.lattice_spacing * b.diameter,
                                b.jitter * b.diameter, static_cast<unsigned>(b.seed));
    sites.insert(sites.end(), pts.begin(), pts.end());
  }
  if (b.count > 0) sites.resize(b.count);
  out.x = sites;
  out.v.assign(sites.size(), Vec<D>::zero());
  for (const auto& one : b.beads) {
    out.x.push_back(to_vec<D>(one.x));
    out.v.push_back(to_vec<D>(one.v));
  }
  return out;
}

// The checkpoint solids.bed names, checked to hold beads of the scene's dimension.
// Needs no Kokkos, so that `dvisph check` reads it too.
inline Checkpoint read_bed(const Scene& s) {
  const std::string& path = s.solids->bed;
  try {
    Checkpoint bed = Checkpoint::read(path);
    if (!bed.has("dem/x")) throw std::runtime_error("holds no beads (no array dem/x)");
    const auto extents = bed.extents("dem/x");
    if (extents.size() != 2 || extents[1] != static_cast<std::size_t>(s.dimension))
      throw std::runtime_error(fmt::format("its beads are not {}D", s.dimension));
    return bed;
  } catch (const std::exception& e) {
    throw SceneError(fmt::format("solids.bed = '{}': {}", path, e.what()));
  }
}

// The beads of a scene: a saved bed (solids.bed) or the scene's own.
template <int D, class Space>
dem::Spheres<D, Space> scene_spheres(const Scene& s) {
  const auto& b = *s.solids;
  if (!b.bed.empty()) {
    const Checkpoint bed = read_bed(s);
    try {
      return dem::read_spheres<D, Space>(bed);
    } catch (const std::exception& e) {
      throw SceneError(fmt::format("solids.bed = '{}': {}", b.bed, e.what()));
    }
  }
  const auto beads = scene_beads<D>(s);
  dem::Spheres<D, Space> spheres(beads.x, 0.5 * b.diameter, b.density, "beads");
  copy_points<D>(beads.v, spheres.v);
  return spheres;
}

// Tank faces (no top face for an open top) and the gate, normals into the beads' side.
template <int D>
std::vector<dem::PlaneWall<D>> scene_walls(const Scene& s) {
  const Vec<D> lo = to_vec<D>(s.tank.lo), hi = to_vec<D>(s.tank.hi);
  std::vector<dem::PlaneWall<D>> walls;
  for (const auto& w : dem::box_walls<D>(lo, hi)) {
    bool periodic = false;  // a face across a periodic axis is no wall
    for (int k = 0; k < D; ++k) periodic = periodic || (w.normal[k] != 0 && s.wraps(k));
    if (!(s.open_top && w.normal[D - 1] < 0) && !periodic) walls.push_back(w);
  }
  if (s.gate) {
    Vec<D> p = lo, n = Vec<D>::zero();
    p[0] = s.gate->x;
    n[0] = -1;
    walls.emplace_back(p, n, s.gate->remove_at);
  }
  return walls;
}

template <int D, class Space>
dem::DemSolver<D, Space> scene_dem(const Scene& s) {
  const auto& b = *s.solids;
  Vec<D> lo = to_vec<D>(s.tank.lo), hi = to_vec<D>(s.tank.hi), g = to_vec<D>(s.gravity);
  // room to bounce above an open top (a periodic axis is the tank's length exactly)
  if (s.open_top && !s.wraps(D - 1)) hi[D - 1] += hi[D - 1] - lo[D - 1];
  dem::DemOptions<D> options;
  options.safety = b.dt_safety;
  options.rotation = b.rotation;
  options.list_skin = b.list_skin;
  options.periodic_axes = s.periodic;
  return dem::DemSolver<D, Space>(scene_spheres<D, Space>(s), scene_walls<D>(s),
                                  dem::LinearSpringDashpot<D>(b.stiffness, b.restitution, b.friction),
                                  lo, hi, g, options);
}

}  // namespace dvisph
