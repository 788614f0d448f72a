#pragma once
// Runs a simulation (simulation.hpp: water, beads or both) through a scene: progress and ETA on a
// terminal, series.csv, HDF5 snapshots, checkpoints, summary.json. A run that fails
// numerically saves its last good state before the error leaves.
#include "src/backend.hpp"
#include "src/checkpoint.hpp"
#include "src/numerical_error.hpp"
#include "src/scene.hpp"
#include "src/snapshot_writer.hpp"

#include <fmt/format.h>
#include <fmt/os.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace dvisph {

struct RunOptions {
  std::string out_dir;
  bool progress = false;  // a progress line on the terminal
  std::string restart;    // checkpoint to continue from ("" none)
};

namespace detail {

inline std::string duration(double s) {
  if (s < 60) return fmt::format("{:.0f}s", s);
  if (s < 3600) return fmt::format("{:.0f}m{:02.0f}s", std::floor(s / 60), std::fmod(s, 60));
  return fmt::format("{:.0f}h{:02.0f}m", std::floor(s / 3600), std::fmod(s / 60, 60));
}

// series.csv: a fresh file, or on restart the rows up to the checkpoint's step kept.
inline std::ofstream open_series(const std::string& path, const std::string& header, long resume_step) {
  std::vector<std::string> kept;
  if (resume_step >= 0) {
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line == header) continue;
      if (std::stol(line.substr(0, line.find(','))) <= resume_step) kept.push_back(line);
    }
  }
  std::ofstream out(path, std::ios::trunc);
  out << header << '\n';
  for (const auto& l : kept) out << l << '\n';
  if (!out.flush()) throw std::runtime_error("cannot write " + path);
  return out;
}

inline std::string join(const std::vector<std::string>& parts, char sep) {
  std::string s;
  for (const auto& p : parts) s += p + sep;
  return s;
}
inline std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::stringstream ss(s);
  for (std::string p; std::getline(ss, p, sep);) parts.push_back(p);
  return parts;
}

}  // namespace detail

template <class Sim>
int run(Sim& sim, const Scene& s, const RunOptions& opt) {
  namespace fs = std::filesystem;
  constexpr char record_sep = '\x1e';
  const std::string out = opt.out_dir;

  // the driver's own state travels in the checkpoint with the simulation's
  double next_snapshot = 0, next_checkpoint = s.checkpoint_every;
  SnapshotWriter writer(out);
  long resume_step = -1;
  if (!opt.restart.empty()) {
    // a checkpoint that is missing, not one, or not of this scene is bad input
    try {
      const Checkpoint c = Checkpoint::read(opt.restart);
      if (c.text("run/scene_name") != s.name)
        throw SceneError(fmt::format("--restart {}: written by scene '{}', not '{}'", opt.restart,
                                     c.text("run/scene_name"), s.name));
      sim.restore(c);
      next_snapshot = c.number("run/next_snapshot");
      next_checkpoint = c.number("run/next_checkpoint");
      writer.resume(detail::split(c.text("run/snapshot_index"), record_sep));
      resume_step = sim.step_count();
    } catch (const SceneError&) {
      throw;
    } catch (const std::runtime_error& e) {
      throw SceneError(fmt::format("--restart {}: {}", opt.restart, e.what()));
    }
  }
  auto save = [&](Checkpoint& c) {
    sim.save(c);
    c.set_text("run/scene_name", s.name);
    c.set("run/t", sim.time());
    c.set_text("run/scene", s.yaml);
    c.set("run/next_snapshot", next_snapshot);
    c.set("run/next_checkpoint", next_checkpoint);
    c.set_text("run/snapshot_index", detail::join(writer.index(), record_sep));
  };

  fs::create_directories(out);
  {
    std::ofstream scene_copy(out + "/scene.yaml");
    scene_copy << s.yaml << '\n';
    if (!scene_copy.flush()) throw std::runtime_error("cannot write " + out + "/scene.yaml");
  }
  auto series = detail::open_series(out + "/series.csv", "step,t,dt," + sim.series_header(), resume_step);
  Kokkos::Timer wall;
  double last_flush = 0;
  auto flush_series = [&] {
    if (!series.flush()) throw std::runtime_error("cannot write " + out + "/series.csv (disk full?)");
    last_flush = wall.seconds();
  };
  // rows reach the file at least every few seconds, so a long run can be watched
  auto record = [&] {
    series << fmt::format("{},{:.9g},{:.6g},{}\n", sim.step_count(), sim.time(), sim.dt(), sim.series_row());
    if (wall.seconds() - last_flush > 2) flush_series();
  };

  const long first_step = sim.step_count();
  const double first_t = sim.time();
  double last_progress = -1;
  if (resume_step < 0) {
    sim.snapshot(writer);
    next_snapshot = s.snapshot_every;
    record();
  }
  // the last good state, kept in memory so a failing step can leave it behind: every
  // steps_between_saves() steps, or up to ten times less often where the copy costs more
  // than 1 % of the steps between (a DEM step is cheap next to it)
  Checkpoint good;
  const long base = sim.steps_between_saves();
  long good_step = -1, save_every = base;
  double saved_at = 0;  // wall seconds at the end of the last save
  try {
    while (sim.time() < s.end_time - 1e-12) {
      if (good_step < 0 || sim.step_count() - good_step >= save_every) {
        const double start = wall.seconds();
        const double per_step = good_step < 0 ? 0 : (start - saved_at) / (sim.step_count() - good_step);
        good = Checkpoint();
        save(good);
        saved_at = wall.seconds();
        if (per_step > 0)
          save_every = std::clamp(static_cast<long>(std::ceil(100 * (saved_at - start) / per_step)), base, 10 * base);
        good_step = sim.step_count();
      }
      sim.step();
      if (sim.step_count() % s.series_every == 0) record();
      if (s.snapshot_every > 0 && sim.time() >= next_snapshot - 1e-12) {
        sim.snapshot(writer);
        next_snapshot += s.snapshot_every;
        flush_series();
      }
      if (s.checkpoint_every > 0 && sim.time() >= next_checkpoint - 1e-12) {
        next_checkpoint += s.checkpoint_every;
        flush_series();
        Checkpoint c;
        save(c);
        c.write(out + "/checkpoint.h5");
      }
      if (opt.progress && wall.seconds() - last_progress > 0.5) {
        last_progress = wall.seconds();
        const double eta =
            wall.seconds() * (s.end_time - sim.time()) / std::max(sim.time() - first_t, 1e-30);
        fmt::print(stderr, "\rstep {:7d}  t {:.4f}/{:.4f} s  dt {:.2e} s  {}  ETA {}   ",
                   sim.step_count(), sim.time(), s.end_time, sim.dt(), sim.progress(),
                   detail::duration(eta));
      }
    }
  } catch (const NumericalError& e) {
    series.flush();
    const std::string path = out + "/last_good.h5";
    good.write(path);
    throw NumericalError(fmt::format("{}\nthe last good state (step {}, t = {:.6g} s) is in {}; "
                                     "`dvisph run SCENE --restart {}` continues from it",
                                     e.what(), good_step, good.number("run/t"), path, path));
  }
  if (opt.progress) fmt::print(stderr, "\n");
  if (sim.step_count() % s.series_every != 0) record();
  if (s.snapshot_every == 0 || std::abs(writer.count() * s.snapshot_every - sim.time()) > 1e-9)
    sim.snapshot(writer);
  flush_series();
  {
    Checkpoint c;
    save(c);
    c.write(out + "/checkpoint.h5");
  }

  const double seconds = wall.seconds();
  const long steps = sim.step_count() - first_step;
  const double ns = 1e9 * seconds / std::max(1.0, double(steps) * sim.particle_count());
  const auto backend = backend_info();
  sim.write_files(out);
  const std::string metrics = sim.metrics();
  std::ofstream summary(out + "/summary.json");
  summary << fmt::format(
      "{{\n  \"scene\": \"{}\",\n  \"dimension\": {},\n  \"backend\": \"{}\",\n  \"threads\": {},\n"
      "  \"kokkos\": \"{}\",\n  \"restarted_from_step\": {},\n  \"steps\": {},\n"
      "  \"end_time\": {:.9g},\n  \"wall_seconds\": {:.3f},\n  \"ns_per_particle_step\": {:.2f},\n"
      "{}  \"metrics\": {{{}}}\n}}\n",
      s.name, s.dimension, backend.backend, backend.concurrency, backend.kokkos_version, resume_step,
      sim.step_count(), sim.time(), seconds, ns, sim.summary(), metrics);
  if (!summary.flush()) throw std::runtime_error("cannot write " + out + "/summary.json");
  fmt::print("{}: {} steps to t = {:.4g} s in {:.1f} s ({:.0f} ns/particle-step); {}\n", s.name,
             steps, sim.time(), seconds, ns, metrics);
  return 0;
}

}  // namespace dvisph
