#include "src/scene.hpp"

#include "src/core/lattice_sites.hpp"
#include "src/schema.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace dvisph {
namespace {

// The most particles, beads or grid cells a run may have: src/core/grid.hpp refuses more
// cells, and particles are indexed by int.
constexpr double max_count = 1 << 30;

std::string join_names(const std::vector<Field>& fields) {
  std::string s;
  for (const auto& f : fields) s += (s.empty() ? "" : ", ") + f.name;
  return s;
}

// A value for a message, cut short: it may be a whole document.
std::string show(const YAML::Node& n) {
  YAML::Emitter e;
  e << YAML::Flow << n;
  const std::string text = e.c_str();
  return text.size() <= 80 ? text : text.substr(0, 77) + "...";
}

double as_number(const YAML::Node& n, const std::string& path) {
  double v;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v) || !std::isfinite(v))
    throw SceneError(fmt::format("{}: '{}' is not a number", path, show(n)));
  return v;
}

void check_range(const Field& f, double v, const std::string& path, const std::string& unit) {
  const bool low = f.min_exclusive ? !(v > f.min) : !(v >= f.min);
  if (low || v > f.max) {
    std::string allowed;
    if (f.min > -1e299) allowed += fmt::format("{} {:g}", f.min_exclusive ? ">" : ">=", f.min);
    if (f.max < 1e299) allowed += fmt::format("{}<= {:g}", allowed.empty() ? "" : " and ", f.max);
    throw SceneError(fmt::format("{} = {:g}{}: out of range, must be {}", path, v,
                                 unit.empty() ? "" : " " + unit, allowed));
  }
}

void validate(const Field& f, const YAML::Node& n, const std::string& path, int dim) {
  switch (f.type) {
    case FieldType::number: check_range(f, as_number(n, path), path, f.unit); break;
    case FieldType::integer: {
      const double v = as_number(n, path);
      if (v != std::floor(v)) throw SceneError(fmt::format("{}: '{}' is not an integer", path, show(n)));
      check_range(f, v, path, f.unit);
      break;
    }
    case FieldType::boolean: {
      bool b;
      if (!n.IsScalar() || !YAML::convert<bool>::decode(n, b))
        throw SceneError(fmt::format("{}: '{}' is not true or false", path, show(n)));
      break;
    }
    case FieldType::choice: {
      if (!n.IsScalar()) throw SceneError(fmt::format("{}: '{}' is not text", path, show(n)));
      if (f.choices.empty()) break;
      const auto v = n.as<std::string>();
      for (const auto& c : f.choices)
        if (c == v) return;
      std::string allowed;
      for (const auto& c : f.choices) allowed += (allowed.empty() ? "" : ", ") + c;
      throw SceneError(fmt::format("{} = '{}': not one of {}", path, v, allowed));
    }
    case FieldType::vector: {
      if (!n.IsSequence() || static_cast<int>(n.size()) != dim)
        throw SceneError(fmt::format("{}: '{}' must be a list of {} numbers ({})", path, show(n),
                                     dim, f.unit));
      for (std::size_t k = 0; k < n.size(); ++k) as_number(n[k], fmt::format("{}[{}]", path, k));
      break;
    }
    case FieldType::list: {
      if (!n.IsSequence() || n.size() == 0)
        throw SceneError(fmt::format("{}: must be a non-empty list of blocks", path));
      Field item = f;
      item.type = FieldType::map;
      for (std::size_t k = 0; k < n.size(); ++k)
        validate(item, n[k], fmt::format("{}[{}]", path, k), dim);
      break;
    }
    case FieldType::map: {
      const std::string where = path.empty() ? "the scene" : path;
      if (!n.IsMap()) throw SceneError(fmt::format("{}: must be a block of keys", where));
      for (const auto& kv : n) {
        if (!kv.first.IsScalar())
          throw SceneError(fmt::format("{}: key '{}' is not a name", where, show(kv.first)));
        const auto key = kv.first.as<std::string>();
        bool known = false;
        for (const auto& c : f.children) known = known || c.name == key;
        if (!known)
          throw SceneError(fmt::format("{}: unknown key '{}' (allowed: {})",
                                       where, key, join_names(f.children)));
      }
      for (const auto& c : f.children) {
        const std::string sub = path.empty() ? c.name : path + "." + c.name;
        if (n[c.name]) validate(c, n[c.name], sub, dim);
        else if (c.required)
          throw SceneError(fmt::format("missing required {} '{}'",
                                       c.type == FieldType::map || c.type == FieldType::list
                                           ? "block" : "key",
                                       sub));
      }
      break;
    }
  }
}

// Value at a dotted path, or the schema's default for it (null if it has none).
class Reader {
 public:
  explicit Reader(const YAML::Node& root) : root_(root) {}
  YAML::Node at(const std::string& path) const {
    YAML::Node n = YAML::Clone(root_);
    const Field* f = &scene_schema();
    std::stringstream ss(path);
    std::string part;
    while (std::getline(ss, part, '.')) {
      const Field* next = nullptr;
      for (const auto& c : f->children)
        if (c.name == part) next = &c;
      f = next;
      n = (n && n.IsMap()) ? n[part] : YAML::Node();
    }
    if (n.IsDefined() && !n.IsNull()) return n;
    return f && !f->default_value.empty() ? YAML::Load(f->default_value) : YAML::Node();
  }
  double number(const std::string& p) const { return at(p).as<double>(); }
  int integer(const std::string& p) const { return static_cast<int>(at(p).as<double>()); }
  std::string text(const std::string& p) const { return at(p).as<std::string>(); }
  std::vector<double> vec(const std::string& p) const { return at(p).as<std::vector<double>>(); }

 private:
  YAML::Node root_;
};

Box read_box(const YAML::Node& n) { return {n["lo"].as<std::vector<double>>(), n["hi"].as<std::vector<double>>()}; }

void apply_override(YAML::Node& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  const std::string path = assignment.substr(0, eq);
  if (eq == std::string::npos || path.empty() || path.front() == '.' || path.back() == '.' ||
      path.find("..") != std::string::npos)
    throw SceneError(fmt::format("--set '{}': expected key.path=value", assignment));
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    throw SceneError(fmt::format("--set {}: cannot parse the value: {}", path, e.msg));
  }
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  // yaml-cpp nodes are handles: walk down by reassigning references
  std::vector<YAML::Node> chain{root};
  std::string walked;
  for (std::size_t k = 0; k + 1 < parts.size(); ++k) {
    walked += (k ? "." : "") + parts[k];
    YAML::Node child = chain.back()[parts[k]];
    if (!child.IsDefined() || child.IsNull()) {
      chain.back()[parts[k]] = YAML::Node(YAML::NodeType::Map);
      child = chain.back()[parts[k]];
    }
    if (!child.IsMap())
      throw SceneError(
          fmt::format("--set {}: {} is '{}', not a block of keys", path, walked, show(child)));
    chain.push_back(child);
  }
  chain.back()[parts.back()] = value;
}

void check_box(const Box& b, const std::string& path) {
  for (std::size_t k = 0; k < b.lo.size(); ++k)
    if (!(b.hi[k] > b.lo[k]))
      throw SceneError(fmt::format("{}: hi[{}] = {:g} m must exceed lo[{}] = {:g} m", path, k,
                                   b.hi[k], k, b.lo[k]));
}

// Squared distance from a point to a box (0 inside).
double distance2(const std::vector<double>& x, const Box& b) {
  double d2 = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double out = std::max({b.lo[k] - x[k], 0.0, x[k] - b.hi[k]});
    d2 += out * out;
  }
  return d2;
}

bool interiors_overlap(const Box& a, const Box& b) {
  bool overlap = true;
  for (std::size_t k = 0; k < a.lo.size(); ++k)
    overlap = overlap && a.lo[k] < b.hi[k] && b.lo[k] < a.hi[k];
  return overlap;
}

// Checks that need several keys at once.
void check_solids(const Scene& s) {
  const auto& b = *s.solids;
  const int dim = s.dimension;
  const double r = 0.5 * b.diameter;
  if (b.lattice.empty() && b.beads.empty() && b.bed.empty())
    throw SceneError("solids: no beads; give solids.lattice, solids.beads or solids.bed");
  // the DEM bins the tank (twice as high with an open top) in cells no smaller than a bead
  double cells = 1;
  for (int k = 0; k < dim; ++k) {
    const double side = (s.tank.hi[k] - s.tank.lo[k]) * (k == dim - 1 && s.open_top ? 2 : 1);
    cells *= std::ceil(side / b.diameter);
  }
  if (cells > max_count)
    throw SceneError(fmt::format("geometry.tank: {:.3g} cells of solids.diameter = {:g} m, more "
                                 "than {:.3g}; are the tank and the diameter in metres?",
                                 cells, b.diameter, max_count));
  // every bead wholly inside the tank and behind the gate
  auto check_inside = [&](const std::vector<double>& lo, const std::vector<double>& hi,
                          const std::string& path) {
    for (int k = 0; k < dim; ++k) {
      const double top = k == 0 && s.gate ? s.gate->x : s.tank.hi[k];
      const double reach = s.wraps(k) ? 0 : r;  // no face to reach past
      if (lo[k] - reach < s.tank.lo[k] - 1e-12 || hi[k] + reach > top + 1e-12)
        throw SceneError(fmt::format("{}: beads of diameter {:g} m at [{:g}, {:g}] m along axis {} "
                                     "reach outside [{:g}, {:g}] m (the tank{})",
                                     path, b.diameter, lo[k], hi[k], k, s.tank.lo[k], top,
                                     k == 0 && s.gate ? " behind the gate" : ""));
    }
  };
  // A lattice box fills its bottom layers first, up to solids.count beads over all boxes.
  // Its beads stay inside the hull of its used sites, so hulls apart hold beads apart.
  const double dx = b.lattice_spacing * b.diameter;
  double sites = 0;
  std::vector<std::pair<std::size_t, Box>> hulls;  // lattice boxes with beads
  for (std::size_t l = 0; l < b.lattice.size(); ++l) {
    const auto path = fmt::format("solids.lattice[{}]", l);
    check_box(b.lattice[l], path);
    auto inner = b.lattice[l];
    const double in = std::min(r, 0.5 * dx);  // the outermost centres
    for (int k = 0; k < dim; ++k) inner.lo[k] += in, inner.hi[k] -= in;
    for (int k = 0; k < dim; ++k)
      if (inner.hi[k] < inner.lo[k])
        throw SceneError(fmt::format("{}: thinner than solids.diameter = {:g} m along axis {}",
                                     path, b.diameter, k));
    check_inside(inner.lo, inner.hi, path);
    Box hull = b.lattice[l];
    double per_layer = 1, layers = 0;
    for (int k = 0; k < dim; ++k) {
      const double n = lattice_sites(hull.hi[k] - hull.lo[k], dx);
      hull.hi[k] = hull.lo[k] + n * dx;
      if (k < dim - 1) per_layer *= n;
      else layers = n;
    }
    const double in_box = per_layer * layers;
    const double used = b.count > 0 ? std::clamp(b.count - sites, 0.0, in_box) : in_box;
    if (used > 0) {
      hull.hi[dim - 1] = hull.lo[dim - 1] + std::ceil(used / per_layer) * dx;
      hulls.emplace_back(l, hull);
    }
    sites += in_box;
  }
  if (sites > max_count)
    throw SceneError(fmt::format("solids.lattice: {:.3g} sites at solids.lattice_spacing = {:g} of "
                                 "solids.diameter = {:g} m, more than {:.3g}",
                                 sites, b.lattice_spacing, b.diameter, max_count));
  if (b.count > sites)
    throw SceneError(fmt::format("solids.count = {}: the lattice boxes hold only {:.0f} beads at "
                                 "solids.lattice_spacing = {:g}",
                                 b.count, sites, b.lattice_spacing));
  for (std::size_t i = 0; i < hulls.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (interiors_overlap(hulls[i].second, hulls[j].second))
        throw SceneError(fmt::format("solids.lattice[{}] overlaps the beads of solids.lattice[{}]",
                                     hulls[i].first, hulls[j].first));
  if (b.jitter >= 0.5 * (b.lattice_spacing - 1) && b.jitter > 0 && !b.fixed)
    throw SceneError(fmt::format("solids.jitter = {:g}: beads could overlap, must be < "
                                 "(solids.lattice_spacing - 1) / 2 = {:g}",
                                 b.jitter, 0.5 * (b.lattice_spacing - 1)));
  for (std::size_t i = 0; i < b.beads.size(); ++i) {
    const auto path = fmt::format("solids.beads[{}].position", i);
    check_inside(b.beads[i].x, b.beads[i].x, path);
    for (const auto& [l, hull] : hulls)
      if (distance2(b.beads[i].x, hull) < r * r * (1 - 1e-12))
        throw SceneError(fmt::format("{} reaches into the beads of solids.lattice[{}]", path, l));
    for (std::size_t j = 0; j < i; ++j) {
      double d2 = 0;
      for (int k = 0; k < dim; ++k)
        d2 += (b.beads[i].x[k] - b.beads[j].x[k]) * (b.beads[i].x[k] - b.beads[j].x[k]);
      if (d2 < b.diameter * b.diameter * (1 - 1e-12))
        throw SceneError(fmt::format("{} overlaps solids.beads[{}]", path, j));
    }
  }
}

// A periodic axis has no walls, and its cells must not wrap onto themselves.
void check_periodic(const Scene& s) {
  if (s.solids && s.solids->fixed && s.fluid.empty())
    throw SceneError("solids.fixed = true: a fixed bed needs geometry.fluid (without water "
                     "nothing would move)");
  if (s.solids && !s.solids->fixed && s.solids->lattice_spacing < 1)
    throw SceneError(fmt::format("solids.lattice_spacing = {:g}: beads would overlap, must be >= 1 "
                                 "(below 1 only with solids.fixed: true)",
                                 s.solids->lattice_spacing));
  if (!s.periodic) return;
  const std::string axes = "xyz";
  const int last = s.dimension - 1;
  if (s.gate && s.wraps(0))
    throw SceneError("geometry.gate: a wall across axis x, which geometry.tank.periodic makes "
                     "periodic (a periodic axis has no walls)");
  if (s.wraps(last) && s.open_top)
    throw SceneError(fmt::format("geometry.tank.periodic: axis {} wraps, but geometry.tank.open_top "
                                 "= true puts a free surface above it; set open_top: false",
                                 axes[last]));
  // the largest search over each grid that wraps: the fluid's cells (2h / fluid_cells_per_radius, swept to 2h and,
  // for the beads' forces, to 2 h_c), the coupling's bead cells (2 h_c) and the DEM's
  const double h = s.h_over_dx * s.spacing;
  const double hc = s.coupling && s.coupling->smoothing_length > 0 ? s.coupling->smoothing_length : h;
  for (int k = 0; k < s.dimension; ++k) {
    if (!s.wraps(k)) continue;
    const double L = s.tank.hi[k] - s.tank.lo[k];
    auto need = [&](double cell, double radius, const char* what) {
      const double cells = std::floor(L / cell + 1e-9);
      const double reach = std::ceil(radius / cell - 1e-12);
      if (cells < 2 * reach + 1)
        throw SceneError(fmt::format("geometry.tank.periodic: axis {} is {:g} m long, shorter than "
                                     "{:g} m ({} search radius {:g} m twice and a cell)",
                                     axes[k], L, (2 * reach + 1) * cell, what, radius));
    };
    if (!s.fluid.empty()) {
      const double sites = L / s.spacing;
      if (std::abs(sites - std::round(sites)) > 1e-6)
        throw SceneError(fmt::format("geometry.tank.periodic: axis {} is {:g} m long, {:.6g} times "
                                     "geometry.spacing = {:g} m; a periodic length must be a whole "
                                     "number of spacings (the lattice would leave a gap at the seam)",
                                     axes[k], L, sites, s.spacing));
      need(2 * h / fluid_cells_per_radius, 2 * h, "the fluid's");
      if (uses_multigrid(s.cg_preconditioner))  // its aggregates: CellMultigrid
        need(std::max(4 * s.spacing, 2 * h), 2 * h, "the multigrid aggregates'");
    }
    if (s.coupling) {
      need(2 * h / fluid_cells_per_radius, 2 * hc, "the coupling's");
      need(2 * hc, 2 * hc, "the coupling's");
    }
    if (s.solids && !s.solids->fixed) {
      const double cell = s.solids->diameter * (1 + 0.05 + s.solids->list_skin);  // DemOptions::skin 0.05
      need(cell, cell, "the DEM's contact");
    }
  }
}

void check_consistency(const Scene& s) {
  const char* name_chars = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.";
  if (s.name.empty() || s.name.front() == '.' ||
      s.name.find_first_not_of(name_chars) != std::string::npos)
    throw SceneError(fmt::format("name = '{}': must be letters, digits, '_', '-' and '.', not "
                                 "starting with '.' (it names the output directory)",
                                 s.name));
  check_box(s.tank, "geometry.tank");
  if (!(s.invariance_truncation[0] < s.invariance_truncation[1]))
    throw SceneError(fmt::format(
        "numerics.invariance_truncation_full = {:g}: must be below "
        "numerics.invariance_truncation_none = {:g}",
        s.invariance_truncation[0], s.invariance_truncation[1]));
  if (s.gate && !(s.gate->x > s.tank.lo[0] && s.gate->x < s.tank.hi[0]))
    throw SceneError(fmt::format("geometry.gate.x = {:g} m: must lie inside the tank ({:g}, {:g}) m",
                                 s.gate->x, s.tank.lo[0], s.tank.hi[0]));
  if (s.gate && s.settle_until > s.gate->remove_at)
    throw SceneError(fmt::format(
        "numerics.settle_until = {:g} s: must not pass geometry.gate.remove_at = {:g} s (the "
        "flow after the gate opens is undamped)", s.settle_until, s.gate->remove_at));
  if (s.settle_until > 0 && s.fluid.empty())
    throw SceneError("numerics.settle_until: damps the water, and the scene has no geometry.fluid");
  if (s.fluid.empty() && !s.solids)
    throw SceneError("nothing to simulate: give geometry.fluid, solids, or both");
  if (uses_multigrid(s.cg_preconditioner) && s.pressure_operator != "stored")
    throw SceneError(fmt::format("numerics.cg_preconditioner = {}: needs "
                                 "numerics.pressure_operator = stored (it is '{}')",
                                 s.cg_preconditioner, s.pressure_operator));
  check_periodic(s);
  if (s.solids) check_solids(s);
  if (s.coupling && (s.fluid.empty() || !s.solids))
    throw SceneError("coupling: needs both geometry.fluid and solids");
  if (s.coupling) {
    const auto& c = *s.coupling;
    if (!(c.porosity_min < 1))
      throw SceneError(fmt::format("coupling.porosity_min = {:g}: must lie in (0, 1)", c.porosity_min));
    const double h = s.h_over_dx * s.spacing;
    const double hc = c.smoothing_length > 0 ? c.smoothing_length : h;
    if (c.smoothing_length > 0 && c.smoothing_length < h * (1 - 1e-9))  // h written out is h
      throw SceneError(fmt::format("coupling.smoothing_length = {:g} m: below the fluid's h = "
                                   "numerics.h_over_dx * geometry.spacing = {:g} m",
                                   c.smoothing_length, h));
    if (hc < 0.5 * s.solids->diameter)
      throw SceneError(fmt::format("coupling.smoothing_length = {:g} m: below the bead radius "
                                   "{:g} m (solids.diameter / 2)", hc, 0.5 * s.solids->diameter));
    if (s.viscosity <= 0)
      throw SceneError("material.kinematic_viscosity = 0: the drag of water on beads needs a "
                       "viscous fluid (> 0)");
  }
  const bool coupled_metric = s.metrics_kind == "settling_bead" || s.metrics_kind == "bed_hydrostatic" ||
                              s.metrics_kind == "ergun_bed";
  if (s.metrics_kind == "ergun_bed" && (!s.closed() || !s.solids ||
                                        !s.solids->fixed))
    throw SceneError("metrics.kind = ergun_bed: needs a fixed bed (solids.fixed: true) in a tank "
                     "periodic along every axis (geometry.tank.periodic)");
  if (coupled_metric && !s.coupling)
    throw SceneError(fmt::format("metrics.kind = {}: needs geometry.fluid and solids", s.metrics_kind));
  if (s.gravity.size() != static_cast<std::size_t>(s.dimension))
    throw SceneError(fmt::format("material.gravity: needs {} entries", s.dimension));
  const bool bead_metric = s.metrics_kind.rfind("bead_", 0) == 0;
  if (bead_metric && !s.solids)
    throw SceneError(fmt::format("metrics.kind = {}: needs a solids block", s.metrics_kind));
  if (!bead_metric && !coupled_metric && s.metrics_kind != "none" && s.fluid.empty())
    throw SceneError(fmt::format("metrics.kind = {}: needs geometry.fluid", s.metrics_kind));
  if ((s.metrics_kind == "dam_break" || s.metrics_kind == "bead_collapse") && !(s.column_width > 0))
    throw SceneError(fmt::format("metrics.column_width: required (> 0 m) when metrics.kind = {}",
                                 s.metrics_kind));
  if ((s.metrics_kind == "hydrostatic" || s.metrics_kind == "bed_hydrostatic") && !(s.water_height > 0))
    throw SceneError(fmt::format("metrics.water_height: required (> 0 m) when metrics.kind = {}",
                                 s.metrics_kind));
  if (s.fluid.empty()) return;  // the rest concerns the fluid
  if (!(s.spacing > 0))
    throw SceneError("geometry.spacing: required (> 0 m) when geometry.fluid is given");
  double smallest = 1e300;
  for (int k = 0; k < s.dimension; ++k) smallest = std::min(smallest, s.tank.hi[k] - s.tank.lo[k]);
  if (s.spacing * 2 > smallest)
    throw SceneError(fmt::format("geometry.spacing = {:g} m: larger than half the tank's "
                                 "smallest side ({:g} m)", s.spacing, smallest));
  double particles = 1;  // the lattice over the tank and its walls bounds fluid and walls
  for (int k = 0; k < s.dimension; ++k)
    particles *= (s.tank.hi[k] - s.tank.lo[k]) / s.spacing + 2 * s.wall_layers;
  if (particles > max_count)
    throw SceneError(fmt::format("geometry.spacing = {:g} m: {:.3g} particles in the tank and its "
                                 "walls, more than {:.3g}; is the tank in metres?",
                                 s.spacing, particles, max_count));
  for (std::size_t b = 0; b < s.fluid.size(); ++b) {
    const auto path = fmt::format("geometry.fluid[{}]", b);
    const auto& f = s.fluid[b];
    check_box(f, path);
    for (int k = 0; k < s.dimension; ++k) {
      if (f.lo[k] < s.tank.lo[k] - 1e-12 || f.hi[k] > s.tank.hi[k] + 1e-12)
        throw SceneError(fmt::format("{}: axis {} spans [{:g}, {:g}] m, outside the tank "
                                     "[{:g}, {:g}] m", path, k, f.lo[k], f.hi[k],
                                     s.tank.lo[k], s.tank.hi[k]));
      if (f.hi[k] - f.lo[k] < s.spacing)
        throw SceneError(fmt::format("{}: thinner than geometry.spacing = {:g} m along axis {}",
                                     path, s.spacing, k));
    }
    for (std::size_t o = 0; o < b; ++o)
      if (interiors_overlap(f, s.fluid[o]))
        throw SceneError(fmt::format("{} overlaps geometry.fluid[{}]", path, o));
  }
  // active walls (within 2h of fluid) need their own full support inside the band
  const int c = static_cast<int>(std::ceil(2 * s.h_over_dx - 1e-9));
  if (s.wall_layers < 2 * c - 2)
    throw SceneError(fmt::format("geometry.wall_layers = {}: too few for numerics.h_over_dx = {:g}, "
                                 "need at least {}", s.wall_layers, s.h_over_dx, 2 * c - 2));
}

}  // namespace

Scene parse_scene(const std::string& yaml_text, const std::vector<std::string>& overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw SceneError(fmt::format("not valid YAML: {}", e.what()));
  }
  if (!root.IsMap()) throw SceneError("the scene must be a block of keys");
  for (const auto& o : overrides) apply_override(root, o);

  // dimension first: vectors are checked against it
  const auto& schema = scene_schema();
  if (!root["dimension"]) throw SceneError("missing required key 'dimension'");
  for (const auto& f : schema.children)
    if (f.name == "dimension") validate(f, root["dimension"], "dimension", 0);
  const int dim = static_cast<int>(as_number(root["dimension"], "dimension"));
  validate(schema, root, "", dim);

  const Reader r(root);
  Scene s;
  s.name = r.text("name");
  s.dimension = dim;
  s.end_time = r.number("end_time");
  s.density = r.number("material.density");
  s.viscosity = r.number("material.kinematic_viscosity");
  if (!r.at("material.gravity").IsNull()) s.gravity = r.vec("material.gravity");
  else {
    s.gravity.assign(dim, 0.0);
    s.gravity[dim - 1] = -9.81;
  }
  if (!r.at("geometry.spacing").IsNull()) s.spacing = r.number("geometry.spacing");
  s.wall_layers = r.integer("geometry.wall_layers");
  s.jitter = r.number("geometry.jitter");
  s.tank = {r.vec("geometry.tank.lo"), r.vec("geometry.tank.hi")};
  s.open_top = r.at("geometry.tank.open_top").as<bool>();
  if (const auto axes = r.text("geometry.tank.periodic"); axes != "none")
    for (const char a : axes) {
      const int k = a - 'x';
      if (k >= dim)
        throw SceneError(fmt::format("geometry.tank.periodic = '{}': a {}D scene has no axis {}",
                                     axes, dim, a));
      s.periodic |= 1u << k;
    }
  for (const auto& b : root["geometry"]["fluid"]) s.fluid.push_back(read_box(b));
  if (root["solids"]) {
    Scene::Solids b;
    b.diameter = r.number("solids.diameter");
    b.density = r.number("solids.density");
    b.restitution = r.number("solids.restitution");
    b.stiffness = r.number("solids.stiffness");
    b.friction = r.number("solids.friction");
    b.dt_safety = r.number("solids.dt_safety");
    b.rotation = r.at("solids.rotation").as<bool>();
    b.fixed = r.at("solids.fixed").as<bool>();
    b.list_skin = r.number("solids.list_skin");
    for (const auto& l : root["solids"]["lattice"]) b.lattice.push_back(read_box(l));
    b.lattice_spacing = r.number("solids.lattice_spacing");
    b.jitter = r.number("solids.jitter");
    b.seed = r.integer("solids.seed");
    b.count = r.integer("solids.count");
    for (const auto& one : root["solids"]["beads"])
      b.beads.push_back({one["position"].as<std::vector<double>>(),
                         one["velocity"] ? one["velocity"].as<std::vector<double>>()
                                         : std::vector<double>(dim, 0.0)});
    if (root["solids"]["bed"]) b.bed = r.text("solids.bed");
    s.solids = b;
  }
  if (!s.fluid.empty() && s.solids) {
    s.coupling = Scene::Coupling{r.number("coupling.smoothing_length"),
                                 r.number("coupling.porosity_min"),
                                 r.number("coupling.switch_porosity"), r.text("coupling.drag"),
                                 r.text("coupling.virtual_mass") == "van_gent",
                                 r.at("coupling.porosity_rate").as<bool>()};
  } else if (root["coupling"]) {
    throw SceneError("coupling: needs both geometry.fluid and solids");
  }
  if (root["geometry"]["gate"])
    s.gate = Scene::Gate{r.number("geometry.gate.x"), r.number("geometry.gate.remove_at")};
  s.no_slip = r.text("boundary.slip") == "no_slip";
  s.kernel = r.text("numerics.kernel");
  s.h_over_dx = r.number("numerics.h_over_dx");
  s.gamma = r.number("numerics.gamma");
  s.alpha = r.at("numerics.alpha").IsNull() ? s.gamma : r.number("numerics.alpha");
  s.beta = r.at("numerics.beta").IsNull() ? s.gamma : r.number("numerics.beta");
  s.cfl = r.number("numerics.cfl");
  s.dt_max = r.number("numerics.dt_max");
  s.cg_tolerance = r.number("numerics.cg_tolerance");
  s.cg_density_tolerance = r.number("numerics.cg_density_tolerance");
  s.cg_max_iterations = r.integer("numerics.cg_max_iterations");
  s.cg_preconditioner = r.text("numerics.cg_preconditioner");
  s.chebyshev_degree = r.integer("numerics.chebyshev_degree");
  s.chebyshev_ratio = r.number("numerics.chebyshev_ratio");
  s.pressure_operator = r.text("numerics.pressure_operator");
  s.surface_criterion = r.text("numerics.surface_criterion");
  s.invariance_truncation[0] = r.number("numerics.invariance_truncation_full");
  s.invariance_truncation[1] = r.number("numerics.invariance_truncation_none");
  s.ghost_air = r.text("numerics.ghost_air");
  s.surface_divergence_threshold = r.number("numerics.surface_divergence_threshold");
  s.surface_density_threshold = r.number("numerics.surface_density_threshold");
  s.reorder_every = r.integer("numerics.reorder_every");
  s.settle_until = r.number("numerics.settle_until");
  s.settle_time = r.number("numerics.settle_time");
  s.snapshot_every = r.number("output.snapshot_every");
  s.series_every = r.integer("output.series_every");
  s.checkpoint_every = r.number("output.checkpoint_every");
  s.metrics_kind = r.text("metrics.kind");
  s.density_error_at = r.number("metrics.density_error_at");
  s.column_width = r.number("metrics.column_width");
  s.water_height = r.number("metrics.water_height");
  check_consistency(s);
  YAML::Emitter e;
  e << root;
  if (!e.good())
    throw SceneError(fmt::format("cannot write the scene back as YAML: {}", e.GetLastError()));
  s.yaml = e.c_str();
  return s;
}

std::vector<std::string> scene_warnings(const Scene& s) {
  std::vector<std::string> out;
  const char* axes = "xyz";
  for (std::size_t b = 0; b < s.fluid.size(); ++b)
    for (int k = 0; k < s.dimension; ++k) {
      const double side = s.fluid[b].hi[k] - s.fluid[b].lo[k];
      const double layers = lattice_sites(side, s.spacing);
      if (side - layers * s.spacing > 1e-6 * s.spacing)
        out.push_back(fmt::format(
            "geometry.fluid[{}] is {:g} m along {}, {:.4g} spacings of {:g} m: the lattice fills {:g} "
            "of them ({:g} m)",
            b, side, axes[k], side / s.spacing, s.spacing, layers, layers * s.spacing));
    }
  return out;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw SceneError(fmt::format("cannot read scene file '{}'", path));
  std::stringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), overrides);
}

}  // namespace dvisph
