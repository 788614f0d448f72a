#pragma once
// Runs a scene with the ISPH solver: progress, series.csv, snapshots, summary.json.
#include "solvers/isph/isph_solver.hpp"
#include "src/backend.hpp"
#include "src/metrics.hpp"
#include "src/snapshot_writer.hpp"

#include <fmt/format.h>
#include <fmt/os.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

namespace dvisph {

struct RunOptions {
  std::string out_dir;
  bool progress = false;  // a progress line on the terminal
};

namespace detail {

inline std::string duration(double s) {
  if (s < 60) return fmt::format("{:.0f}s", s);
  if (s < 3600) return fmt::format("{:.0f}m{:02.0f}s", std::floor(s / 60), std::fmod(s, 60));
  return fmt::format("{:.0f}h{:02.0f}m", std::floor(s / 3600), std::fmod(s / 60, 60));
}

template <int D, class Solver>
void snapshot(const Solver& solver, SnapshotWriter& writer) {
  const auto& p = solver.particles();
  const int n = solver.size();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.kind);
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.id);
  auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver.pressure());
  auto rho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver.density());
  std::vector<double> xs(n * D);
  std::vector<int> kinds(n);
  SnapshotField vel{"velocity", D, std::vector<double>(n * D)}, pres{"pressure", 1, {}},
      dens{"density", 1, {}}, ids{"id", 1, {}}, roles{"role", 1, {}};
  auto role = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver.roles());
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < D; ++k) xs[i * D + k] = x(i, k), vel.values[i * D + k] = v(i, k);
    kinds[i] = static_cast<int>(kind(i));
    pres.values.push_back(pr(i, 0));
    dens.values.push_back(rho(i));
    ids.values.push_back(id(i));
    roles.values.push_back(static_cast<int>(role(i)));
  }
  writer.write(solver.info().t, D, xs, {vel, pres, dens, ids, roles}, kinds);
}

}  // namespace detail

template <int D, class Kernel>
int run_scene(const Scene& s, const RunOptions& opt) {
  using Space = Kokkos::DefaultExecutionSpace;
  namespace fs = std::filesystem;
  IsphSolver<D, Kernel, Space> solver(s);

  fs::create_directories(opt.out_dir);
  {
    auto scene_copy = fmt::output_file(opt.out_dir + "/scene.yaml");
    scene_copy.print("{}\n", s.yaml);
  }
  SnapshotWriter writer(opt.out_dir);
  auto series = fmt::output_file(opt.out_dir + "/series.csv");
  series.print("step,t,dt,cg_iterations,cg_residual,max_speed,front,max_density_error\n");

  const bool dam_break = s.metrics_kind == "dam_break";
  const double g = std::abs(s.gravity[D - 1]);
  FrontData front_sim;
  double max_density_error_seen = 0;
  long cg_total = 0;
  int cg_max = 0;

  auto record = [&](const StepInfo& info) {
    const double front =
        front_position<Space>(solver.particles().x, solver.particles().kind, solver.size()) -
        s.tank.lo[0];
    const double derr =
        max_density_error<Space>(solver.density(), solver.pressure(), solver.particles().kind,
                                 solver.reference_density(), solver.size());
    if (info.step > 0) max_density_error_seen = std::max(max_density_error_seen, derr);
    series.print("{},{:.9g},{:.6g},{},{:.3g},{:.6g},{:.6g},{:.6g}\n", info.step, info.t, info.dt,
                 info.cg_iterations, info.cg_residual, info.max_speed, front, derr);
    if (dam_break) {
      front_sim.T.push_back(info.t * std::sqrt(2 * g / s.column_width));
      front_sim.Z.push_back(front / s.column_width);
    }
  };

  Kokkos::Timer wall;
  double next_snapshot = 0, last_progress = -1;
  detail::snapshot<D>(solver, writer);
  next_snapshot += s.snapshot_every;
  record(solver.info());
  while (solver.info().t < s.end_time - 1e-12) {
    const StepInfo& info = solver.step();
    cg_total += info.cg_iterations;
    cg_max = std::max(cg_max, info.cg_iterations);
    if (info.step % s.series_every == 0) record(info);
    if (s.snapshot_every > 0 && info.t >= next_snapshot - 1e-12) {
      detail::snapshot<D>(solver, writer);
      next_snapshot += s.snapshot_every;
      series.flush();
    }
    if (opt.progress && wall.seconds() - last_progress > 0.5) {
      last_progress = wall.seconds();
      const double eta = wall.seconds() * (s.end_time - info.t) / std::max(info.t, 1e-30);
      fmt::print(stderr, "\rstep {:7d}  t {:.4f}/{:.4f} s  dt {:.2e} s  CG {:4d}  ETA {}   ",
                 info.step, info.t, s.end_time, info.dt, info.cg_iterations, detail::duration(eta));
    }
  }
  if (opt.progress) fmt::print(stderr, "\n");
  const StepInfo& info = solver.info();
  if (info.step % s.series_every != 0) record(info);
  if (s.snapshot_every == 0 || std::abs(writer.count() * s.snapshot_every - info.t) > 1e-9)
    detail::snapshot<D>(solver, writer);
  series.close();

  const double seconds = wall.seconds();
  std::string metrics = fmt::format("\"max_density_error\": {:.6g}", max_density_error_seen);
  if (dam_break) {
    int points = 0;
    const auto data = martin_moyce();
    const double rms = front_rms_deviation(front_sim, data, 1.0, 3.0, &points);
    const double lag = best_front_lag(front_sim, data, 1.0, 3.0);
    metrics += fmt::format(
        ", \"front_rms_deviation_T1_3\": {:.6g}, \"front_points_compared\": {}, "
        "\"front_best_lag_T\": {:.4g}, \"front_rms_deviation_T1_3_after_lag\": {:.6g}",
        rms, points, lag, front_rms_deviation(front_sim, data, 1.0, 3.0, nullptr, lag));
  }
  if (s.metrics_kind == "hydrostatic") {
    const auto e = hydrostatic_errors<D>(solver, s);
    metrics += fmt::format(
        ", \"pressure_max_error_over_rho_g_H\": {:.6g}, \"pressure_rms_error_over_rho_g_H\": {:.6g}, "
        "\"pressure_max_pointwise_relative_error\": {:.6g}, \"pressure_particles_checked\": {}",
        e.max_over_rho_g_H, e.rms_over_rho_g_H, e.max_pointwise, e.checked);
  }
  std::string stage_times;
  for (const auto& st : solver.stages())
    stage_times += fmt::format("{}\"{}\": {:.4f}", stage_times.empty() ? "" : ", ", st.name, st.seconds);

  const auto backend = backend_info();
  auto summary = fmt::output_file(opt.out_dir + "/summary.json");
  summary.print(
      "{{\n  \"scene\": \"{}\",\n  \"dimension\": {},\n  \"backend\": \"{}\",\n  \"threads\": {},\n"
      "  \"kokkos\": \"{}\",\n  \"kernel\": \"{}\",\n  \"particles\": {{\"fluid\": {}, \"wall\": {}, "
      "\"gate\": {}}},\n  \"steps\": {},\n  \"end_time\": {:.9g},\n  \"wall_seconds\": {:.3f},\n"
      "  \"ns_per_particle_step\": {:.2f},\n  \"pairs\": {},\n  \"cg_iterations_mean\": {:.2f},\n"
      "  \"cg_iterations_max\": {},\n  \"stage_seconds\": {{{}}},\n  \"metrics\": {{{}}}\n}}\n",
      s.name, D, backend.backend, backend.concurrency, backend.kokkos_version, Kernel::name,
      solver.count(Kind::fluid), solver.count(Kind::wall), solver.count(Kind::gate), info.step,
      info.t, seconds, 1e9 * seconds / std::max(1.0, double(info.step) * solver.size()),
      solver.pairs(), double(cg_total) / std::max<long>(1, info.step), cg_max, stage_times, metrics);
  summary.close();
  fmt::print("{}: {} steps to t = {:.4g} s in {:.1f} s ({:.0f} ns/particle-step), CG mean {:.1f} "
             "max {}; {}\n",
             s.name, info.step, info.t, seconds,
             1e9 * seconds / std::max(1.0, double(info.step) * solver.size()),
             double(cg_total) / std::max<long>(1, info.step), cg_max, metrics);
  return 0;
}

}  // namespace dvisph
