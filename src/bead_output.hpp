#pragma once
// What series.csv, the snapshots and summary.json hold for the beads of a scene
// (src/simulation.hpp composes it with the water's). Figures by metrics.kind: bead_drop
// (rebound restitution), bead_collision (momentum, restitution), bead_slide (rolling
// speed or stop distance), bead_bed (packing fraction, bed height) and bead_collapse
// (bead front); energy throughout (without the water's work on the beads).
#include "src/connected_front.hpp"
#include "src/numerical_error.hpp"
#include "src/scene_beads.hpp"
#include "src/snapshot_part.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace dvisph {

template <int D, class Space = Kokkos::DefaultExecutionSpace>
class BeadOutput {
 public:
  // `with_water`: the series columns get a bead_ prefix, the stage times their own key
  BeadOutput(const Scene& s, const dem::DemSolver<D, Space>& dem, bool with_water)
      : s_(s), dem_(dem), g_(std::abs(s.gravity[D - 1])), prefix_(with_water ? "bead_" : ""),
        front_of_(s.tank.lo[0], s.tank.hi[0], s.solids->diameter, 2) {
    const bool few = s.metrics_kind == "bead_drop" || s.metrics_kind == "bead_collision" ||
                     s.metrics_kind == "bead_slide";
    if (few && dem_.spheres().n > 2)
      throw SceneError(fmt::format("metrics.kind = {}: follows one or two beads, the scene has {}",
                                   s.metrics_kind, dem_.spheres().n));
    watch_ = few;
    if (watch_) {
      auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dem_.spheres().mass);
      mass_ = m(0);  // the scene's beads are alike
      const auto b = beads();
      p0_ = momentum(b);
      v0_ = std::sqrt(dot(b.v[0], b.v[0]));
      x0_ = b.x[0];
      if (b.v.size() == 2) dv0_ = b.v[1][0] - b.v[0][0];
    }
    energy0_ = last_energy_ = dem_.energy().total();
  }

  long steps() const { return step_; }
  // after each step of the DEM or the water
  void after_step() {
    ++step_;
    if (watch_) follow();
  }

  std::string series_header() const {
    std::string h;
    for (const char* c : {"kinetic_energy", "total_energy", "max_speed", "front"})
      h += (h.empty() ? "" : ",") + prefix_ + c;
    return h + ",bed_top";
  }
  std::string series_row() {
    const dem::Energy e = dem_.energy();
    if (step_ > 0) energy_rise_ = std::max(energy_rise_, e.total() - last_energy_);
    last_energy_ = e.total();
    const auto& sp = dem_.spheres();
    const auto x = sp.x, v = sp.v;
    const auto r = sp.radius;
    Real speed = 0, top = -1e300;
    Kokkos::parallel_reduce(
        "dvisph::dem_run::extent", Kokkos::RangePolicy<Space>(0, sp.n),
        KOKKOS_LAMBDA(int i, Real& s, Real& t) {
          Real v2 = 0;
          for (int k = 0; k < D; ++k) v2 += v(i, k) * v(i, k);
          s = math::max(s, math::sqrt(v2));
          t = math::max(t, x(i, D - 1) + r(i));
        },
        Kokkos::Max<Real>(speed), Kokkos::Max<Real>(top));
    // the leading edge of the body of beads (slabs of one diameter, two empty ones end it)
    const Real front = front_of_(LeadingEdge<decltype(x), decltype(r)>{x, r}, sp.n) - s_.tank.lo[0];
    if (s_.metrics_kind == "bead_collapse") {
      collapse_T_ = (dem_.time() - s_.metrics_origin()) * std::sqrt(2 * g_ / s_.column_width);
      collapse_Z_ = front / s_.column_width;
    }
    return fmt::format("{:.9g},{:.9g},{:.6g},{:.6g},{:.6g}", e.kinetic, e.total(), speed, front,
                       top - s_.tank.lo[D - 1]);
  }

  SnapshotPart snapshot() const {
    const auto& sp = dem_.spheres();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.x);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.v);
    auto w = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.omega);
    auto r = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.radius);
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.id);
    constexpr int R = dem::rot_dim<D>;
    const int n = sp.n;
    std::vector<double> xs(n * D);
    SnapshotField vel{"velocity", D, std::vector<double>(n * D)},
        omega{"angular_velocity", R, std::vector<double>(n * R)}, radius{"radius", 1, {}},
        ids{"id", 1, {}};
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < D; ++k) xs[i * D + k] = x(i, k), vel.values[i * D + k] = v(i, k);
      for (int c = 0; c < R; ++c) omega.values[i * R + c] = w(i, c);
      radius.values.push_back(r(i));
      ids.values.push_back(id(i));
    }
    return {xs, std::vector<int>(n, static_cast<int>(Kind::solid)), {vel, omega, radius, ids}};
  }

  void save(Checkpoint& c) const {
    c.set("dem_run/step", static_cast<double>(step_));
    c.set("dem_run/energy_rise", energy_rise_);
    c.set("dem_run/last_energy", last_energy_);
    c.set("dem_run/contact", contact_);
    c.set("dem_run/v_in", v_in_);
    c.set("dem_run/v_out", v_out_);
    c.set("dem_run/t_in", t_in_);
    c.set("dem_run/t_out", t_out_);
    c.set("dem_run/stopped_at", stopped_at_);
  }
  void restore(const Checkpoint& c) {
    step_ = static_cast<long>(c.number("dem_run/step"));
    energy_rise_ = c.number("dem_run/energy_rise");
    last_energy_ = c.number("dem_run/last_energy");
    contact_ = static_cast<int>(c.number("dem_run/contact"));
    v_in_ = c.number("dem_run/v_in");
    v_out_ = c.number("dem_run/v_out");
    t_in_ = c.number("dem_run/t_in");
    t_out_ = c.number("dem_run/t_out");
    stopped_at_ = c.number("dem_run/stopped_at");
  }

  // "name": seconds of each DEM stage over this process's steps
  std::string stage_times() const {
    std::string t;
    for (std::size_t k = 0; k < dem_.stage_seconds().size(); ++k)
      t += fmt::format("{}\"{}\": {:.4f}", k ? ", " : "", dem_.stage_names[k], dem_.stage_seconds()[k]);
    return t;
  }

  std::string particles() const { return fmt::format("\"solid\": {}", dem_.spheres().n); }

  std::string summary() const {
    const auto& b = *s_.solids;
    return fmt::format(
        "  \"dem\": {{\"dt\": {:.6g}, \"contact_time\": {:.6g}, \"contacts_per_bead\": {:.3f}, "
        "\"list_builds\": {}}},\n  \"{}stage_seconds\": {{{}}},\n",
        dem_.time_step(), dem_.time_step() / b.dt_safety, dem_.contacts_per_bead(),
        dem_.list_builds(), prefix_.empty() ? "" : "dem_", stage_times());
  }

  std::string metrics() const {
    const auto& b = *s_.solids;
    std::string m = fmt::format("\"energy_initial\": {:.9g}, \"energy_largest_rise\": {:.3g}",
                                energy0_, energy_rise_);
    const auto& kind = s_.metrics_kind;
    if (kind == "bead_drop" && contact_ == 2)
      m += fmt::format(", \"restitution_set\": {:g}, \"impact_speed\": {:.6g}, \"rebound_speed\": "
                       "{:.6g}, \"contact_duration\": {:.6g}, \"restitution\": {:.6g}",
                       b.restitution, v_in_, v_out_, t_out_ - t_in_, v_out_ / v_in_);
    if (kind == "bead_collision") {
      const auto beads_now = beads();
      const Vec<D> p = momentum(beads_now);
      Real scale = 0;
      for (std::size_t i = 0; i < beads_now.v.size(); ++i)
        scale += mass_ * std::sqrt(dot(beads_now.v[i], beads_now.v[i]));
      const Vec<D> dp = p - p0_;
      const Real dv = beads_now.v.size() == 2 ? beads_now.v[1][0] - beads_now.v[0][0] : 0;
      m += fmt::format(", \"momentum_change_relative\": {:.3g}, \"restitution_set\": {:g}, "
                       "\"restitution\": {:.6g}",
                       std::sqrt(dot(dp, dp)) / scale, b.restitution, -dv / dv0_);
    }
    if (kind == "bead_slide") {
      const auto now = beads();
      const Real v = std::sqrt(dot(now.v[0], now.v[0]));
      if (b.rotation)
        m += fmt::format(", \"launch_speed\": {:.6g}, \"final_speed\": {:.6g}, "
                         "\"final_over_launch\": {:.6g}, \"expected_over_launch\": {:.6g}",
                         v0_, v, v / v0_, 5.0 / 7.0);
      else {
        const Vec<D> d = now.x[0] - x0_;
        m += fmt::format(", \"launch_speed\": {:.6g}, \"stop_distance\": {:.6g}, "
                         "\"expected_stop_distance\": {:.6g}, \"stopped_at\": {:.6g}",
                         v0_, std::sqrt(dot(d, d)), v0_ * v0_ / (2 * b.friction * g_), stopped_at_);
      }
    }
    if (kind == "bead_bed") m += bed_figures();
    if (kind == "bead_collapse")
      m += fmt::format(", \"front_T\": {:.4g}, \"front_Z\": {:.4g}", collapse_T_, collapse_Z_);
    return m;
  }

 private:
  struct HostBeads {
    std::vector<Vec<D>> x, v;
  };
  HostBeads beads() const {
    const auto& sp = dem_.spheres();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.x);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.v);
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.id);
    HostBeads b{std::vector<Vec<D>>(sp.n), std::vector<Vec<D>>(sp.n)};
    for (int i = 0; i < sp.n; ++i)
      for (int k = 0; k < D; ++k) b.x[id(i)][k] = x(i, k), b.v[id(i)][k] = v(i, k);
    return b;
  }
  Vec<D> momentum(const HostBeads& b) const {
    Vec<D> p = Vec<D>::zero();
    for (const auto& v : b.v) p += mass_ * v;
    return p;
  }

  // bead_drop: the first impact on the floor, measured at step resolution; bead_slide
  // without rotation: when the bead stops.
  void follow() {
    const auto b = beads();
    const Real gap = b.x[0][D - 1] - 0.5 * s_.solids->diameter - s_.tank.lo[D - 1];
    if (s_.metrics_kind == "bead_drop") {
      if (contact_ == 0 && gap < 0) contact_ = 1, t_in_ = dem_.time();
      else if (contact_ == 0) v_in_ = -b.v[0][D - 1];
      else if (contact_ == 1 && gap >= 0) contact_ = 2, t_out_ = dem_.time(), v_out_ = b.v[0][D - 1];
    }
    if (s_.metrics_kind == "bead_slide" && stopped_at_ < 0 && dot(b.v[0], b.v[0]) < 1e-12)
      stopped_at_ = dem_.time();
  }

  // Packing fraction in the core of the bed (two diameters from the side walls, the
  // floor and the surface) and the height the beads would fill at that packing.
  std::string bed_figures() const {
    const auto b = beads();
    const Real d = s_.solids->diameter, r = 0.5 * d;
    const Real vol = D == 3 ? math::pi / 6 * d * d * d : math::pi / 4 * d * d;  // per bead
    Real top = -1e300;
    for (const auto& x : b.x) top = std::max(top, x[D - 1] + r);
    Vec<D> lo = to_vec<D>(s_.tank.lo), hi = to_vec<D>(s_.tank.hi);
    hi[D - 1] = top;
    Real core = 1, footprint = 1;
    Vec<D> clo, chi;
    for (int k = 0; k < D; ++k) {
      clo[k] = lo[k] + 2 * d;
      chi[k] = hi[k] - 2 * d;
      core *= chi[k] - clo[k];
      if (k < D - 1) footprint *= hi[k] - lo[k];
    }
    // volume of the beads inside the core box, by sampling each bead's slab overlap
    // along the vertical (exact for the side faces to within one bead per face)
    Real inside = 0;
    for (const auto& x : b.x) {
      bool in = true;
      for (int k = 0; k < D - 1; ++k) in = in && x[k] >= clo[k] && x[k] <= chi[k];
      if (!in) continue;
      const Real a = std::clamp((x[D - 1] - clo[D - 1]) / r, -1.0, 1.0);
      const Real c = std::clamp((chi[D - 1] - x[D - 1]) / r, -1.0, 1.0);
      // fraction of a sphere (3D) or disc (2D) between heights -a r.. c r from its centre
      auto below = [](Real z) {  // fraction below z r, z in [-1, 1]
        return D == 3 ? 0.25 * (z + 1) * (z + 1) * (2 - z)
                      : (z * std::sqrt(1 - z * z) + std::asin(z) + 0.5 * math::pi) / math::pi;
      };
      inside += vol * (below(c) - below(-a));
    }
    const Real phi = inside / core;
    const Real height = b.x.size() * vol / (phi * footprint);
    return fmt::format(", \"beads\": {}, \"packing_fraction_core\": {:.4f}, \"bed_height\": {:.5g}, "
                       "\"bed_top\": {:.5g}",
                       b.x.size(), phi, height, top - lo[D - 1]);
  }

  Scene s_;
  const dem::DemSolver<D, Space>& dem_;
  Real g_;
  std::string prefix_;
  ConnectedFront<Space> front_of_;
  long step_ = 0;
  bool watch_ = false;
  Real energy0_ = 0, last_energy_ = 0, energy_rise_ = 0;
  Vec<D> p0_ = Vec<D>::zero(), x0_ = Vec<D>::zero();
  Real v0_ = 0, dv0_ = 0, mass_ = 0;
  int contact_ = 0;  // bead_drop: 0 falling, 1 touching the floor, 2 rebounded
  Real v_in_ = 0, v_out_ = 0, t_in_ = 0, t_out_ = 0, stopped_at_ = -1;
  Real collapse_T_ = 0, collapse_Z_ = 0;
};

}  // namespace dvisph
