#pragma once
// The solvers a scene has, composed into one simulation for the run driver (run.hpp):
// water alone (IsphSolver with clear water), beads alone (DemSolver, one DEM step per
// step) or both (IsphSolver with a porous medium, which advances the DEM inside its
// step with the water's forces). What each set writes (series columns, snapshot
// fields, checkpoint entries, figures) comes from its output (fluid_output.hpp,
// bead_output.hpp, coupled_output.hpp); this class only joins them.
#include "src/bead_output.hpp"
#include "src/coupled_output.hpp"
#include "src/fluid_output.hpp"
#include "src/scene_beads.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <optional>
#include <string>

namespace dvisph {

template <int D, class Kernel, class Medium, class Space = Kokkos::DefaultExecutionSpace>
class Simulation {
 public:
  using Fluid = IsphSolver<D, Kernel, Space, Medium>;
  using Beads = dem::DemSolver<D, Space>;
  // water and beads together (the scene has both: main.cpp picks the porous medium)
  static constexpr bool coupled = is_porous<Medium>;

  explicit Simulation(const Scene& s) : s_(s) {
    const bool water = !s.fluid.empty();
    if (s.solids) {
      beads_.emplace(scene_dem<D, Space>(s));
      bead_out_.emplace(s, *beads_, water);
    }
    if (water) {
      fluid_.emplace(s, beads_ ? &*beads_ : nullptr);
      fluid_out_.emplace(s, *fluid_);
    }
    if constexpr (coupled) coupled_out_.emplace(s, *fluid_, *beads_);
  }
  Simulation(const Simulation&) = delete;  // the fluid solver holds the beads' address
  Simulation& operator=(const Simulation&) = delete;

  void step() {
    if (fluid_) {
      fluid_out_->after_step(fluid_->step());
    } else {
      try {
        beads_->step(beads_->time_step());
      } catch (const std::runtime_error& e) {
        throw NumericalError(fmt::format("step {}, t = {:.6g} s: {}", step_count() + 1, time(), e.what()));
      }
    }
    if (bead_out_) bead_out_->after_step();
    if constexpr (coupled) coupled_out_->after_step();
  }
  long step_count() const { return fluid_ ? fluid_->info().step : bead_out_->steps(); }
  double time() const { return fluid_ ? fluid_->info().t : beads_->time(); }
  double dt() const { return fluid_ ? fluid_->info().dt : beads_->time_step(); }
  long particle_count() const { return (fluid_ ? fluid_->size() : 0) + (beads_ ? beads_->spheres().n : 0); }
  // the last good state is a copy of the whole state to the host: for water every 10th
  // step (a failing run redoes at most 10 steps from last_good.h5); a DEM step is cheap
  // next to the copy
  long steps_between_saves() const { return fluid_ ? 10 : 100; }
  std::string progress() const {
    std::string p = fluid_ ? fmt::format("CG {:4d}", fluid_->info().cg_iterations) : "";
    if (beads_) p += fmt::format("{}{} beads", p.empty() ? "" : "  ", beads_->spheres().n);
    return p;
  }

  std::string series_header() const {
    std::string h;
    if (fluid_out_) append(h, fluid_out_->series_header());
    if (bead_out_) append(h, bead_out_->series_header());
    if constexpr (coupled) append(h, coupled_out_->series_header());
    return h;
  }
  std::string series_row() {
    std::string r;
    if (fluid_out_) append(r, fluid_out_->series_row());
    if (bead_out_) append(r, bead_out_->series_row());
    if constexpr (coupled) append(r, coupled_out_->series_row());
    return r;
  }

  // One snapshot with every particle: the fields of either set, zero on the other's.
  void snapshot(SnapshotWriter& writer) const {
    SnapshotPart all;
    auto add = [&](SnapshotPart part) {
      const std::size_t before = all.kind.size(), n = part.kind.size();
      all.x.insert(all.x.end(), part.x.begin(), part.x.end());
      all.kind.insert(all.kind.end(), part.kind.begin(), part.kind.end());
      for (auto& f : all.fields) f.values.resize((before + n) * f.components, 0.0);
      for (auto& f : part.fields) {
        auto it = std::find_if(all.fields.begin(), all.fields.end(),
                               [&](const SnapshotField& a) { return a.name == f.name; });
        if (it == all.fields.end()) {
          all.fields.push_back({f.name, f.components, std::vector<double>(before * f.components, 0.0)});
          it = all.fields.end() - 1;
          it->values.insert(it->values.end(), f.values.begin(), f.values.end());
        } else {
          std::copy(f.values.begin(), f.values.end(), it->values.begin() + before * f.components);
        }
      }
    };
    if (fluid_out_) add(fluid_out_->snapshot());
    if (bead_out_) add(bead_out_->snapshot());
    writer.write(time(), D, all.x, all.fields, all.kind);
  }

  void save(Checkpoint& c) const {
    if (fluid_) fluid_->save(c), fluid_out_->save(c);
    if (beads_) beads_->save(c), bead_out_->save(c);
  }
  void restore(const Checkpoint& c) {
    if (fluid_) fluid_->restore(c), fluid_out_->restore(c);
    if (beads_) beads_->restore(c), bead_out_->restore(c);
  }

  void write_files(const std::string& out) const {
    if (fluid_out_) fluid_out_->write_files(out);
  }
  std::string summary() const {
    std::string particles;
    if (fluid_out_) particles = fluid_out_->particles();
    if (bead_out_) particles += (particles.empty() ? "" : ", ") + bead_out_->particles();
    std::string s = fmt::format("  \"particles\": {{{}}},\n", particles);
    if (fluid_out_) s += fluid_out_->summary();
    if (bead_out_) s += bead_out_->summary();
    return s;
  }
  std::string metrics() const {
    std::string m;
    auto add = [&](const std::string& part) { m += (m.empty() || part.empty() ? "" : ", ") + part; };
    if (fluid_out_) add(fluid_out_->metrics());
    if (bead_out_) add(bead_out_->metrics());
    if constexpr (coupled) add(coupled_out_->metrics());
    return m;
  }

 private:
  static void append(std::string& columns, const std::string& more) {
    columns += (columns.empty() ? "" : ",") + more;
  }

  Scene s_;
  std::optional<Beads> beads_;  // before the fluid solver, which holds its address
  std::optional<Fluid> fluid_;
  std::optional<FluidOutput<D, Fluid>> fluid_out_;
  std::optional<BeadOutput<D, Space>> bead_out_;
  std::optional<CoupledOutput<D, Fluid>> coupled_out_;
};

}  // namespace dvisph
