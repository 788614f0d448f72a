#pragma once
// A scene: the typed content of a validated scene file (see src/schema.cpp).
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dvisph {

// Bad input: the message names the key, the value and what is allowed (exit code 2).
// Cells of the fluid's neighbour grid per kernel radius (IsphSolver): a sweep then
// scans 5^D cells of half a radius instead of 3^D of a radius, 0.58 of the volume in 3D
// (fewer candidate pairs to test).
constexpr int fluid_cells_per_radius = 2;

struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Box {
  std::vector<double> lo, hi;
};

struct Scene {
  std::string name;
  int dimension = 2;
  double end_time = 0;

  double density = 1000, viscosity = 0;
  std::vector<double> gravity;

  double spacing = 0;
  int wall_layers = 3;
  double jitter = 0;  // fluid start positions, over spacing
  Box tank;
  bool open_top = true;
  unsigned periodic = 0;  // geometry.tank.periodic: bit k set when axis k wraps
  bool wraps(int k) const { return (periodic >> k & 1u) != 0; }
  // every axis wraps: no wall and no free surface
  bool closed() const { return periodic == (1u << dimension) - 1; }
  std::vector<Box> fluid;
  struct Gate {
    double x, remove_at;
  };
  std::optional<Gate> gate;
  // the time from which the figures of a gated scene count (metrics.*): the gate's removal
  double metrics_origin() const { return gate ? gate->remove_at : 0; }

  struct Bead {
    std::vector<double> x, v;
  };
  struct Solids {
    double diameter, density, restitution, stiffness, friction, dt_safety, list_skin;
    bool rotation;
    bool fixed = false;  // held where they start (a fixed bed): no DEM step
    std::vector<Box> lattice;
    double lattice_spacing, jitter;
    int seed, count;
    std::vector<Bead> beads;
    std::string bed;  // checkpoint to start from ("" none)
  };
  std::optional<Solids> solids;
  // water and beads together: the coupling block (defaults where it is absent)
  struct Coupling {
    double smoothing_length;  // h_c [m]; 0: the fluid's h
    double porosity_min, switch_porosity;
    std::string drag;
    bool virtual_mass;
    bool porosity_rate;  // d eps/dt of the moving beads in the PPE's source
  };
  std::optional<Coupling> coupling;

  bool no_slip = true;

  std::string kernel;
  double h_over_dx = 1.5, gamma = 0.1, cfl = 0.25, dt_max = 1e-3, cg_tolerance = 1e-8, cg_density_tolerance = 1e-6;
  double alpha = 0.1, beta = 0.1;  // numerics.alpha / beta, each numerics.gamma unless given
  int cg_max_iterations = 2000;
  std::string cg_preconditioner = "jacobi";  // jacobi, chebyshev, multigrid, additive_multigrid
  int chebyshev_degree = 3;
  double chebyshev_ratio = 30;
  std::string pressure_operator = "stored";
  std::string surface_criterion = "position_divergence";
  double surface_divergence_threshold = 0.75, surface_density_threshold = 0.95;
  double invariance_truncation[2] = {0.15, 0.4};  // full, none
  std::string ghost_air = "everywhere";
  int reorder_every = 25;
  double settle_until = 0, settle_time = 0.01;  // damped start [s] (0: none)

  double snapshot_every = 0;
  int series_every = 1;
  double checkpoint_every = 0;

  std::string metrics_kind = "none";
  double column_width = 0, water_height = 0;
  double density_error_at = 0;  // s; 0: none

  std::string yaml;  // the scene as validated, overrides applied
};

// Whether numerics.cg_preconditioner is one of the cell multigrid's (solvers/cell_multigrid.hpp).
inline bool uses_multigrid(const std::string& preconditioner) {
  return preconditioner == "multigrid" || preconditioner == "additive_multigrid";
}

// Reads, overrides (`key.path=value`), validates and converts a scene file.
// Throws SceneError on any bad input.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
Scene parse_scene(const std::string& yaml_text, const std::vector<std::string>& overrides = {});

// What a valid scene may not mean as written (e.g. a fluid box that is not a whole
// number of spacings: the lattice fills less of it). One line each.
std::vector<std::string> scene_warnings(const Scene& s);

}  // namespace dvisph
