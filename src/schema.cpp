#include "src/schema.hpp"

#include <fmt/format.h>

#include <sstream>

namespace dvisph {
namespace {

constexpr double inf = 1e300;

Field number(std::string name, std::string unit, std::string def, double min, double max,
             std::string help, bool min_exclusive = false) {
  Field f{std::move(name), FieldType::number, std::move(unit), std::move(help)};
  f.default_value = std::move(def);
  f.required = f.default_value.empty();
  f.min = min;
  f.max = max;
  f.min_exclusive = min_exclusive;
  return f;
}
Field integer(std::string name, std::string def, double min, double max, std::string help) {
  Field f = number(std::move(name), "", std::move(def), min, max, std::move(help));
  f.type = FieldType::integer;
  return f;
}
Field boolean(std::string name, std::string def, std::string help) {
  Field f{std::move(name), FieldType::boolean, "", std::move(help)};
  f.default_value = std::move(def);
  return f;
}
Field choice(std::string name, std::string def, std::vector<std::string> choices,
             std::string help) {
  Field f{std::move(name), FieldType::choice, "", std::move(help)};
  f.default_value = std::move(def);
  f.required = f.default_value.empty();
  f.choices = std::move(choices);
  return f;
}
Field vector(std::string name, std::string unit, std::string def, std::string help) {
  Field f{std::move(name), FieldType::vector, std::move(unit), std::move(help)};
  f.default_value = std::move(def);
  f.required = f.default_value.empty();
  return f;
}
Field optional(Field f) {
  f.required = false;
  return f;
}
Field map(std::string name, bool required, std::vector<Field> children, std::string help) {
  Field f{std::move(name), FieldType::map, "", std::move(help)};
  f.required = required;
  f.children = std::move(children);
  return f;
}
Field list(std::string name, bool required, std::vector<Field> item, std::string help) {
  Field f = map(std::move(name), required, std::move(item), std::move(help));
  f.type = FieldType::list;
  return f;
}
// the keys of a box in a list of boxes
std::vector<Field> corners() {
  return {vector("lo", "m", "", "lower corner"), vector("hi", "m", "", "upper corner")};
}

Field make_schema() {
  return map(
      "", true,
      {
          choice("name", "scene", {},
                 "scene name, used in outputs (letters, digits, `_`, `-`, `.`)"),
          integer("dimension", "", 2, 3, "spatial dimension: 2 or 3"),
          number("end_time", "s", "", 0, inf, "simulated time to run", true),
          map("material", false,
              {
                  number("density", "kg/m^3", "1000", 0, inf, "fluid reference density", true),
                  number("kinematic_viscosity", "m^2/s", "1.0e-6", 0, 1,
                         "fluid kinematic viscosity; 0 runs no viscosity loop"),
                  optional(vector("gravity", "m/s^2", "", "gravity vector, one entry per dimension "
                                                          "(default: -9.81 along the last axis)")),
              },
              "fluid properties"),
          map("geometry", true,
              {
                  optional(number("spacing", "m", "", 0, inf,
                                  "initial fluid particle spacing dx (required with fluid)", true)),
                  integer("wall_layers", "4", 1, 12,
                          "layers of wall particles; at least 2 ceil(2h/dx) - 2 so that wall "
                          "particles near the fluid have full support"),
                  number("jitter", "", "0", 0, 0.25,
                         "random offset of each fluid particle along each axis at the start, "
                         "over spacing (stress tests; reproducible)"),
                  map("tank", true,
                      {
                          vector("lo", "m", "", "lower corner of the inner tank faces"),
                          vector("hi", "m", "", "upper corner of the inner tank faces"),
                          boolean("open_top", "true", "no wall on the top face"),
                          choice("periodic", "none", {"none", "x", "y", "z", "xy", "xz", "yz", "xyz"},
                                 "axes along which the tank wraps (no walls there: what leaves "
                                 "through one face comes back through the other; water, beads, "
                                 "pairs and the pressure solve all wrap); its length must be a "
                                 "whole number of spacings, and the last axis wraps only with "
                                 "open_top: false"),
                      },
                      "tank: box of wall particles around the fluid"),
                  list("fluid", false,
                       corners(),
                       "boxes filled with fluid particles (a list of lo/hi maps); a scene "
                       "without fluid runs the DEM alone"),
                  map("gate", false,
                      {
                          number("x", "m", "", -inf, inf, "position of the gate plane (first axis)"),
                          number("remove_at", "s", "0", 0, inf, "time at which the gate is removed"),
                      },
                      "optional gate: a wall plane across the tank, removed at a given time"),
              },
              "what is where"),
          map("solids", false,
              {
                  number("diameter", "m", "", 0, inf, "bead diameter d", true),
                  number("density", "kg/m^3", "2500", 0, inf, "bead density", true),
                  number("restitution", "", "0.9", 0, 1,
                         "coefficient of restitution e (sets the normal dashpot)", true),
                  number("stiffness", "N/m", "1000", 0, inf, "normal spring k_n", true),
                  number("friction", "", "0.2", 0, 10, "Coulomb friction coefficient mu"),
                  number("dt_safety", "", "0.04", 0, 0.1,
                         "DEM step over the binary contact time of the lightest pair; above 0.1 "
                         "a contact gets too few steps and strongly damped beds gain energy "
                         "(docs/stability.md)", true),
                  boolean("rotation", "true", "false: beads do not rotate (torques ignored)"),
                  boolean("fixed", "false",
                          "true: the beads stay where they start (a fixed bed, e.g. the Ergun "
                          "check): no DEM step, no contacts; the water's forces on them are "
                          "still computed and reported. Needs geometry.fluid"),
                  number("list_skin", "", "0.1", 0, 2,
                         "Verlet list skin over the bead diameter: pairs this much farther apart "
                         "than the contact search are listed, and the list is rebuilt once a "
                         "bead has moved half of it"),
                  list("lattice", false,
                       corners(),
                       "boxes filled with beads on a square lattice, bottom layer first"),
                  number("lattice_spacing", "", "1.1", 0.5, 10,
                         "lattice: distance between bead centres over d; at least 1 unless "
                         "solids.fixed (a fixed bed's beads are only volume spread over the "
                         "water, so a dense bed may overlap them)"),
                  number("jitter", "", "0", 0, 0.5,
                         "lattice: random offset of each bead along each axis, over d; must "
                         "leave the beads apart (< (lattice_spacing - 1) / 2)"),
                  integer("seed", "1", 0, 2147483647, "lattice: seed of the jitter"),
                  integer("count", "0", 0, 1e8,
                          "lattice: number of beads, filling the boxes from the bottom "
                          "(0: every lattice site)"),
                  list("beads", false,
                       {vector("position", "m", "", "centre"),
                        optional(vector("velocity", "m/s", "", "initial velocity (default 0)"))},
                       "single beads (a list of position/velocity maps)"),
                  optional(choice("bed", "", {},
                                  "checkpoint (HDF5) of a settled bed to start from, e.g. "
                                  "out/bead_bed_settle/checkpoint.h5; relative paths are "
                                  "taken from the working directory")),
              },
              "DEM beads (glass beads, method.md section 3); the tank walls and the gate "
              "are planes for them"),
          map("coupling", false,
              {
                  number("smoothing_length", "m", "0", 0, inf,
                         "h_c, the smoothing length of the kernel that spreads the beads over "
                         "the water (porosity, solid velocity) and the water over the beads "
                         "(forces); 0: the fluid's h. At least the bead radius; coupled codes "
                         "find porosity noisy below an averaging volume of about three bead "
                         "diameters"),
                  number("porosity_min", "", "0.3", 0, 1,
                         "smallest porosity a fluid particle takes (eps = max(eps_min, 1 - sum "
                         "V_s W)); the beads' pressure share follows the clamped value, so "
                         "momentum stays exact", true),
                  choice("drag", "ergun_wen_yu", {"ergun_wen_yu", "di_felice"},
                         "drag closure: Ergun below coupling.switch_porosity and Wen & Yu "
                         "above (Gidaspow), or Di Felice (1994)"),
                  number("switch_porosity", "", "0.8", 0, 1,
                         "ergun_wen_yu: porosity eps_d at which the law switches from Ergun to "
                         "Wen & Yu"),
                  choice("virtual_mass", "van_gent", {"van_gent", "none"},
                         "virtual-mass coefficient C_r = 1 + 0.34 (1 - eps) / eps (van Gent), "
                         "or C_r = 1"),
                  boolean("porosity_rate", "true",
                          "the PPE's source takes the rate d eps/dt at which moving beads "
                          "change the porosity (the water's continuity d eps/dt + div v = 0); "
                          "false: eq. 5 as printed, div v* alone, so water makes way for "
                          "moving beads only through the density-invariance term"),
              },
              "water and beads in one scene (method.md §2): how they exchange momentum"),
          map("boundary", false,
              {choice("slip", "no_slip", {"no_slip", "free_slip"},
                      "wall condition for the viscous term")},
              "wall conditions"),
          map("numerics", false,
              {
                  choice("kernel", "wendland_c2", {"cubic_spline", "wendland_c2"},
                         "smoothing kernel (Wendland C2 keeps a square lattice under pressure "
                         "far longer than the cubic spline, not for ever: docs/isph.md)"),
                  number("h_over_dx", "", "1.5", 1.0, 2.5, "smoothing length over spacing"),
                  number("gamma", "", "0.1", 0, 1,
                         "density-invariance (stabilization) parameter of the PPE: alpha = "
                         "beta = gamma, one pressure solve (the conventional method)"),
                  optional(number("alpha", "", "", 0, 1,
                                  "stabilization parameter of the PPE whose pressure gives the "
                                  "physical velocity (method.md §1; default numerics.gamma)")),
                  optional(number("beta", "", "", 0, 1,
                                  "stabilization parameter of the PPE whose pressure gives the "
                                  "transport velocity, which only moves the particles (default "
                                  "numerics.gamma); beta != alpha solves the PPE for both")),
                  number("cfl", "", "0.25", 0, 1, "Courant number on h / max|v|", true),
                  number("dt_max", "s", "1.0e-3", 0, inf, "largest time step", true),
                  number("cg_tolerance", "", "1.0e-8", 1e-14, 1e-1,
                         "relative residual at which CG stops"),
                  number("cg_density_tolerance", "", "1.0e-6", 0, 1e-1,
                         "CG also stops once its residual leaves no particle a density change "
                         "per step above this (dt^2 |r_i| / rho0; 0: off)"),
                  integer("cg_max_iterations", "2000", 1, 1e6, "CG iteration cap"),
                  choice("cg_preconditioner", "jacobi",
                         {"jacobi", "chebyshev", "multigrid", "additive_multigrid"},
                         "CG's preconditioner: the diagonal, a Chebyshev polynomial in it "
                         "(chebyshev_degree - 1 more matrix applications per iteration), a "
                         "V-cycle over cell aggregates (two more per iteration and a set-up per "
                         "step; needs pressure_operator: stored), or the diagonal plus that "
                         "V-cycle from the first aggregates down (no more applications, more "
                         "iterations than multigrid); the last three take fewer iterations "
                         "than jacobi (docs/isph.md)"),
                  integer("chebyshev_degree", "3", 2, 32,
                          "degree of the Chebyshev preconditioner"),
                  number("chebyshev_ratio", "", "30", 1.5, 1e6,
                         "the Chebyshev preconditioner approximates the inverse on "
                         "eigenvalues of D^-1 A in [2 / ratio, 2]"),
                  choice("pressure_operator", "stored", {"stored", "matrix_free"},
                         "how CG applies the PPE matrix: coefficients stored once per step "
                         "(fast, 12 bytes per neighbour pair) or recomputed from the neighbour "
                         "list at every iteration (least memory)"),
                  choice("surface_criterion", "position_divergence",
                         {"position_divergence", "density"},
                         "free-surface test (P = 0): div r or summation density against its "
                         "interior value"),
                  number("surface_divergence_threshold", "", "0.75", 0.3, 1.0,
                         "position_divergence: div r / interior value below which a particle "
                         "is on the free surface"),
                  number("surface_density_threshold", "", "0.95", 0.5, 1.0,
                         "density: <rho> / interior value below which a particle is on the "
                         "free surface"),
                  number("invariance_truncation_full", "", "0.15", 0, 1.0,
                         "truncation of a fluid particle's support (the length of sum_j V_j "
                         "grad W_ij over its value on a flat free surface) up to which the "
                         "support counts as full: the density-invariance term applies whole"),
                  number("invariance_truncation_none", "", "0.4", 0, 1.0,
                         "truncation from which the support reaches so far into the air that "
                         "the density-invariance term is off (linear in between)"),
                  choice("ghost_air", "everywhere", {"everywhere", "truncated"},
                         "where the PPE adds the free surface's ghost air (P = 0 beyond the "
                         "particles) for the part of a support that is empty: on every fluid "
                         "row, or on truncated supports only, by (1 - invariance weight); "
                         "truncated diverged on a jittered tank (docs/isph.md)"),
                  integer("reorder_every", "25", 0, 1e9,
                          "steps between reorderings of particles by cell (0: never)"),
                  number("settle_until", "s", "0", 0, inf,
                         "a damped start: until this time the water's velocity relaxes as "
                         "exp(-dt / settle_time) each step, so that water set on a lattice "
                         "(and a bed in it) settles into the solver's equilibrium (0: none); "
                         "at most geometry.gate.remove_at"),
                  number("settle_time", "s", "0.01", 0, inf,
                         "time scale of the damped start's relaxation", true),
              },
              "numerical parameters"),
          map("output", false,
              {
                  number("snapshot_every", "s", "0", 0, inf,
                         "interval between HDF5 snapshots (0: first and last only)"),
                  integer("series_every", "1", 1, 1e9, "steps between rows of series.csv"),
                  number("checkpoint_every", "s", "0", 0, inf,
                         "interval between checkpoints, for `dvisph run --restart` (0: at the "
                         "end only); each replaces checkpoint.h5 whole"),
              },
              "what is written"),
          map("metrics", false,
              {
                  choice("kind", "none",
                         {"none", "hydrostatic", "dam_break", "bead_drop", "bead_collision",
                          "bead_slide", "bead_bed", "bead_collapse", "settling_bead",
                          "bed_hydrostatic", "ergun_bed"},
                         "scene-specific figures in summary.json"),
                  number("column_width", "m", "0", 0, inf,
                         "dam_break: width a of the initial water column (Z = z/a, "
                         "T = t sqrt(2 g / a), t from the gate's removal)"),
                  number("water_height", "m", "0", 0, inf,
                         "hydrostatic, bed_hydrostatic: still-water height H for P = rho g (H - y)"),
                  number("density_error_at", "s", "0", 0, inf,
                         "water: time (from the gate's removal, where there is a gate) at which "
                         "the density error's p50, p95, p99 and max go "
                         "into summary.json and its histogram into density_error_histogram.csv "
                         "(the first series row at or after it; 0: none)"),
              },
              "figures the run reports"),
      },
      "scene");
}

const char* type_name(const Field& f) {
  switch (f.type) {
    case FieldType::number: return "number";
    case FieldType::integer: return "integer";
    case FieldType::boolean: return "true/false";
    case FieldType::choice: return "text";
    case FieldType::vector: return "list of numbers (one per dimension)";
    case FieldType::map: return "block";
    case FieldType::list: return "list of blocks";
  }
  return "";
}

std::string range_text(const Field& f) {
  if (f.type == FieldType::choice && !f.choices.empty()) {
    std::string s;
    for (const auto& c : f.choices) s += (s.empty() ? "" : ", ") + ("`" + c + "`");
    return s;
  }
  if (f.type != FieldType::number && f.type != FieldType::integer) return "";
  const std::string lo = f.min <= -inf ? "" : fmt::format("{}{:g}", f.min_exclusive ? "> " : ">= ", f.min);
  const std::string hi = f.max >= inf ? "" : fmt::format("<= {:g}", f.max);
  return lo + (lo.empty() || hi.empty() ? "" : ", ") + hi;
}

void markdown_rows(const Field& f, const std::string& prefix, std::ostringstream& out) {
  for (const auto& c : f.children) {
    const std::string path = prefix.empty() ? c.name : prefix + "." + c.name;
    const std::string def =
        c.required ? "required" : (c.default_value.empty() ? "—" : "`" + c.default_value + "`");
    out << "| `" << path << (c.type == FieldType::list ? "[]" : "") << "` | " << type_name(c)
        << " | " << (c.unit.empty() ? "—" : c.unit) << " | " << def << " | " << range_text(c)
        << " | " << c.help << " |\n";
    if (c.type == FieldType::map || c.type == FieldType::list)
      markdown_rows(c, path + (c.type == FieldType::list ? "[]" : ""), out);
  }
}

}  // namespace

const Field& scene_schema() {
  static const Field schema = make_schema();
  return schema;
}

std::string schema_markdown() {
  std::ostringstream out;
  out << "# Scene files\n\n"
      << "Generated by `build/dvisph schema` from the schema the loader checks against "
         "(src/schema.cpp); do not edit by hand.\n\n"
      << "A scene is a YAML file. Unknown keys, wrong types and values out of range are "
         "rejected with a message naming the key (exit code 2). `dvisph check SCENE` "
         "validates without running; `--set key=value` overrides a key from the command "
         "line (e.g. `--set numerics.cfl=0.2`).\n\n"
      << "| key | type | unit | default | allowed | meaning |\n|---|---|---|---|---|---|\n";
  markdown_rows(scene_schema(), "", out);
  return out.str();
}

}  // namespace dvisph
