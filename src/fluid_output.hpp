#pragma once
// What series.csv, the snapshots and summary.json hold for the water of a scene
// (src/simulation.hpp composes it with the beads'), and the scene's own figures
// (hydrostatic pressure, dam-break front against Martin & Moyce, density error).
#include "solvers/isph/isph_solver.hpp"
#include "src/snapshot_part.hpp"
#include "src/metrics.hpp"
#include "src/snapshot_writer.hpp"

#include <fmt/format.h>

namespace dvisph {

template <int D, class Solver>
class FluidOutput {
 public:
  using Space = typename Solver::execution_space;
  using Kernel = typename Solver::kernel_type;

  FluidOutput(const Scene& s, const Solver& solver)
      : s_(s),
        solver_(solver),
        g_(std::abs(s.gravity[D - 1])),
        dam_break_(s.metrics_kind == "dam_break"),
        walls_(tank_walls<D>(s)),
        front_of_(s.tank.lo[0], s.tank.hi[0], s.spacing,
                  static_cast<int>(std::ceil(solver.kernel().radius() / s.spacing - 1e-9))) {}

  // after each step of the solver
  void after_step(const StepInfo& info) {
    stepped_ = true;
    // alpha != beta: how far the transport velocity takes the particles off the physical
    // velocity's path in a step; beyond about 0.2 h the position correction is no longer
    // a small one (said once)
    const double shift = info.transport_shift / solver_.kernel().h;
    if (shift > 0.2 && max_transport_shift_ <= 0.2)
      fmt::print(stderr,
                 "warning: step {}, t = {:.6g} s: the transport velocity moves particles "
                 "{:.3g} h off the physical velocity's path in one step (above 0.2 h)\n",
                 info.step, info.t, shift);
    max_transport_shift_ = std::max(max_transport_shift_, shift);
    cg_total_ += info.cg_iterations;
    cg_max_ = std::max(cg_max_, info.cg_iterations);
    pair_visits_ +=
        double(solver_.pairs()) * (info.cg_iterations + pair_sweeps_outside_cg(solver_.stages()));
  }
  std::string series_header() const {
    return "cg_iterations,cg_residual,cg_density_residual,max_speed,front,max_density_error,density_error_p95";
  }
  std::string series_row() {
    const auto& p = solver_.particles();
    const auto& info = solver_.info();
    const double front =
        front_of_(FluidFrontCoordinate<decltype(p.x), decltype(p.kind)>{p.x, p.kind}, solver_.size()) -
        s_.tank.lo[0];
    DensityErrorFigures derr;  // none before this process's first step: no neighbour list yet
    if (stepped_) {
      const auto old = density_error_.weighted_rule(p.kind, solver_.density(), solver_.pressure(),
                                                    solver_.invariance(), solver_.reference_density(),
                                                    solver_.size(), solver_.medium());
      worst_weighted_rule_.max = std::max(worst_weighted_rule_.max, old.max);
      worst_weighted_rule_.p95 = std::max(worst_weighted_rule_.p95, old.p95);
      // the paper's rule last: its histogram is the one density_error_ then holds
      derr = density_error_.template paper_rule<D>(solver_.neighbors(), p.kind, solver_.density(),
                                                   solver_.pressure(), solver_.truncation(),
                                                   solver_.reference_density(), solver_.size(),
                                                   solver_.medium());
      worst_.max = std::max(worst_.max, derr.max);
      worst_.p95 = std::max(worst_.p95, derr.p95);
      const double since = info.t - s_.metrics_origin();
      if (s_.density_error_at > 0 && at_.t < 0 && since >= s_.density_error_at - 1e-12)
        at_ = {since, derr, density_error_.histogram()};
    }
    wall_penetration_ =
        std::max(wall_penetration_, wall_penetration<D, Space>(p.x, p.kind, solver_.size(), walls_));
    if (dam_break_ && info.t >= s_.metrics_origin()) {
      front_.T.push_back((info.t - s_.metrics_origin()) * std::sqrt(2 * g_ / s_.column_width));
      front_.Z.push_back(front / s_.column_width);
    }
    return fmt::format("{},{:.3g},{:.3g},{:.6g},{:.6g},{:.6g},{:.6g}", info.cg_iterations,
                       info.cg_residual, info.cg_density_residual, info.max_speed, front, derr.max,
                       derr.p95);
  }

  SnapshotPart snapshot() const {
    const auto& p = solver_.particles();
    const int n = solver_.size();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.v);
    auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.kind);
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.id);
    auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver_.pressure());
    auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver_.density());
    auto role = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver_.roles());
    auto cut = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver_.truncation());
    std::vector<double> xs(n * D);
    std::vector<int> kinds(n);
    SnapshotField vel{"velocity", D, std::vector<double>(n * D)}, pres{"pressure", 1, {}},
        dens{"density", 1, {}}, ids{"id", 1, {}}, roles{"role", 1, {}},
        truncation{"truncation", 1, {}};
    for (int i = 0; i < n; ++i) {
      for (int k = 0; k < D; ++k) xs[i * D + k] = x(i, k), vel.values[i * D + k] = v(i, k);
      kinds[i] = static_cast<int>(kind(i));
      pres.values.push_back(pr(i, 0));
      dens.values.push_back(rho(i));
      ids.values.push_back(id(i));
      roles.values.push_back(static_cast<int>(role(i)));
      truncation.values.push_back(cut(i));
    }
    std::vector<SnapshotField> fields{vel, pres, dens, ids, roles, truncation};
    if constexpr (is_porous<std::decay_t<decltype(solver_.medium())>>) {
      auto eps = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver_.medium().eps);
      fields.push_back({"porosity", 1, std::vector<double>(eps.data(), eps.data() + n)});
    }
    return {xs, kinds, fields};
  }

  void save(Checkpoint& c) const {
    c.set("isph_run/cg_total", static_cast<double>(cg_total_));
    c.set("isph_run/cg_max", cg_max_);
    c.set("isph_run/max_density_error", worst_.max);
    c.set("isph_run/density_error_p95", worst_.p95);
    c.set("isph_run/max_density_error_weighted_rule", worst_weighted_rule_.max);
    c.set("isph_run/density_error_p95_weighted_rule", worst_weighted_rule_.p95);
    c.set("isph_run/wall_penetration", wall_penetration_);
    c.set("isph_run/max_transport_shift", max_transport_shift_);
    c.set("isph_run/at_t", at_.t);
    if (at_.t >= 0) {
      c.set("isph_run/at_max", at_.figures.max);
      c.set("isph_run/at_p50", at_.figures.p50);
      c.set("isph_run/at_p95", at_.figures.p95);
      c.set("isph_run/at_p99", at_.figures.p99);
      c.set("isph_run/at_counted", static_cast<double>(at_.figures.counted));
      c.put("isph_run/at_histogram", host_view(at_.histogram));
    }
    c.put("isph_run/front_T", host_view(front_.T));
    c.put("isph_run/front_Z", host_view(front_.Z));
  }
  void restore(const Checkpoint& c) {
    cg_total_ = static_cast<long>(c.number("isph_run/cg_total"));
    cg_max_ = static_cast<int>(c.number("isph_run/cg_max"));
    worst_.max = c.number("isph_run/max_density_error");
    worst_.p95 = c.number("isph_run/density_error_p95");
    worst_weighted_rule_.max = c.number("isph_run/max_density_error_weighted_rule");
    worst_weighted_rule_.p95 = c.number("isph_run/density_error_p95_weighted_rule");
    wall_penetration_ = c.number("isph_run/wall_penetration");
    max_transport_shift_ = c.number("isph_run/max_transport_shift");
    at_ = {};
    at_.t = c.number("isph_run/at_t");
    if (at_.t >= 0) {
      at_.figures = {c.number("isph_run/at_max"), c.number("isph_run/at_p50"),
                     c.number("isph_run/at_p95"), c.number("isph_run/at_p99"),
                     static_cast<long>(c.number("isph_run/at_counted"))};
      at_.histogram.resize(c.extents("isph_run/at_histogram").at(0));
      c.get("isph_run/at_histogram", host_view(at_.histogram));
    }
    for (auto* v : {&front_.T, &front_.Z}) {
      const std::string name = v == &front_.T ? "isph_run/front_T" : "isph_run/front_Z";
      v->resize(c.extents(name).at(0));
      c.get(name, host_view(*v));
    }
  }

  std::string particles() const {
    return fmt::format("\"fluid\": {}, \"wall\": {}, \"gate\": {}", solver_.count(Kind::fluid),
                       solver_.count(Kind::wall), solver_.count(Kind::gate));
  }

  std::string summary() const {
    std::string stage_times;
    double step_seconds = 0;  // this process's steps, as pair_visits_
    for (const auto& st : solver_.stages()) {
      stage_times += fmt::format("{}\"{}\": {:.4f}", stage_times.empty() ? "" : ", ", st.name, st.seconds);
      step_seconds += st.seconds;
    }
    const long steps = std::max(1L, solver_.info().step);
    return fmt::format(
        "  \"kernel\": \"{}\",\n"
        "  \"pairs\": {},\n  \"neighbor_list_full_builds\": {},\n"
        "  \"pair_interactions_per_second\": {:.4g},\n  \"cg_iterations_mean\": {:.2f},\n"
        "  \"cg_iterations_max\": {},\n  \"stage_seconds\": {{{}}},\n"
        "  \"memory_bytes\": {},\n  \"memory_bytes_per_particle\": {:.0f},\n",
        Kernel::name, solver_.pairs(), solver_.neighbor_list_full_builds(), pair_visits_ / std::max(step_seconds, 1e-30),
        double(cg_total_) / steps, cg_max_, stage_times, solver_.memory_bytes(),
        double(solver_.memory_bytes()) / std::max(1, solver_.size()));
  }

  // Files besides the driver's: the density error's histogram at metrics.density_error_at.
  void write_files(const std::string& out) const {
    if (at_.t < 0) return;
    const std::string path = out + "/density_error_histogram.csv";
    std::ofstream f(path);
    f << "# |<rho> - rho_ref| / rho_ref of counted particles (src/metrics.hpp) at t = "
      << fmt::format("{:.6g}", at_.t) << " s; bins of 1/" << DensityError<Space>::per_decade
      << " decade, the last open above\nlower,upper,count\n";
    const int bins = static_cast<int>(at_.histogram.size());
    for (int b = 0; b < bins; ++b)
      f << fmt::format("{:.6g},{},{}\n", DensityError<Space>::bin_lower(b),
                       b + 1 < bins ? fmt::format("{:.6g}", DensityError<Space>::bin_lower(b + 1)) : "inf",
                       at_.histogram[b]);
    if (!f.flush()) throw std::runtime_error("cannot write " + path);
  }

  std::string metrics() const {
    std::string m = fmt::format(
        "\"max_density_error\": {:.6g}, \"density_error_p95\": {:.6g}, "
        "\"max_density_error_weighted_rule\": {:.6g}, \"density_error_p95_weighted_rule\": {:.6g}, "
        "\"wall_penetration_over_dx\": {:.4g}",
        worst_.max, worst_.p95, worst_weighted_rule_.max, worst_weighted_rule_.p95,
        wall_penetration_ / s_.spacing);
    if (s_.alpha != s_.beta) m += fmt::format(", \"max_transport_shift_over_h\": {:.4g}", max_transport_shift_);
    if (at_.t >= 0)
      m += fmt::format(
          ", \"density_error_at\": {{\"t\": {:.6g}, \"p50\": {:.4g}, \"p95\": {:.4g}, "
          "\"p99\": {:.4g}, \"max\": {:.6g}, \"counted\": {}}}",
          at_.t, at_.figures.p50, at_.figures.p95, at_.figures.p99, at_.figures.max, at_.figures.counted);
    if (dam_break_) {
      int points = 0;
      const auto data = martin_moyce();
      const double rms = front_rms_deviation(front_, data, 1.0, 3.0, &points);
      const double lag = best_front_lag(front_, data, 1.0, 3.0);
      m += fmt::format(
          ", \"front_rms_deviation_T1_3\": {:.6g}, \"front_points_compared\": {}, "
          "\"front_best_lag_T\": {:.4g}, \"front_rms_deviation_T1_3_after_lag\": {:.6g}",
          rms, points, lag, front_rms_deviation(front_, data, 1.0, 3.0, nullptr, lag));
    }
    if (s_.metrics_kind == "hydrostatic") {
      const auto e = hydrostatic_errors<D>(solver_, s_);
      m += fmt::format(
          ", \"pressure_max_error_over_rho_g_H\": {:.6g}, \"pressure_rms_error_over_rho_g_H\": "
          "{:.6g}, \"pressure_max_pointwise_relative_error\": {:.6g}, "
          "\"pressure_particles_checked\": {}",
          e.max_over_rho_g_H, e.rms_over_rho_g_H, e.max_pointwise, e.checked);
    }
    return m;
  }

 private:
  template <class T>
  static auto host_view(std::vector<T>& v) {
    return Kokkos::View<T*, Kokkos::HostSpace, Kokkos::MemoryUnmanaged>(v.data(), v.size());
  }
  template <class T>
  static auto host_view(const std::vector<T>& v) {
    return Kokkos::View<const T*, Kokkos::HostSpace, Kokkos::MemoryUnmanaged>(v.data(), v.size());
  }

  Scene s_;
  const Solver& solver_;
  double g_;
  bool dam_break_;
  FrontData front_;
  TankWalls<D> walls_;
  ConnectedFront<Space> front_of_;
  // largest over the series rows of the density error's max and p95 over particles:
  // the paper's rule, and the rule before it (metrics.hpp)
  DensityErrorFigures worst_, worst_weighted_rule_;
  double wall_penetration_ = 0;   // m, deepest over the series rows
  double max_transport_shift_ = 0;  // largest dt max|v_transport - v| / h over the steps
  DensityError<Space> density_error_;
  // the density error at metrics.density_error_at (t < 0: not reached or not asked)
  struct AtTime {
    double t = -1;
    DensityErrorFigures figures;
    std::vector<long> histogram;
  } at_;
  bool stepped_ = false;  // a step ran in this process (the density error needs its neighbours)
  double pair_visits_ = 0;        // neighbour pairs swept by this process's steps
  long cg_total_ = 0;
  int cg_max_ = 0;
};

}  // namespace dvisph
