// Cost of a DEM step (kick-drift, rebinning, contact forces with history, kick) per bead,
// for the paper's glass beads in a dense bed in a box, at 1e4, 1e5 and 1e6 beads, on
// Serial and the default execution space. Also the binning alone (rebuilt every step),
// a reorder by cell, and steps before it, on beads shuffled in memory. Writes JSON (one
// record per case) to argv[1]; `--no-serial` skips the Serial cases (for a second run
// at another thread count).
//
// The bed: a simple cubic lattice compressed to 0.998 d with +-0.0005 d jitter, at rest
// under gravity, shuffled in memory, then reordered by cell as a run would keep it.
// Every bead presses on its 6 lattice neighbours (overlaps of about 5 um), the
// coordination of a dense random packing; the solid fraction is 0.52 against about 0.6
// for random close packing, so the sweep meets about 15 % fewer non-touching candidates.
#include "benchmarks/timer.hpp"
#include "solvers/dem/dem_solver.hpp"
#include "src/lattice.hpp"

#include <fmt/core.h>
#include <fmt/os.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace dvisph;
using namespace dvisph::dem;

namespace {

struct Record {
  std::string backend;
  int threads;
  long n;
  double step_ns = 0, step_min_ns = 0, shuffled_step_ns = 0, bin_ns = 0, reorder_ns = 0,
         contacts_per_bead = 0;
};

template <class Space>
Record run(long target_n) {
  const Real d = 2.7e-3, rho = 2500, k_n = 1000, spacing = 0.998 * d;
  const int side = static_cast<int>(std::round(std::cbrt(double(target_n))));
  Vec<3> lo, hi;
  for (int k = 0; k < 3; ++k) lo[k] = 0, hi[k] = side * spacing + 0.5 * (d - spacing);
  hi[2] += 2 * d;  // headroom
  auto pts = lattice<3>(lo, hi, spacing, 0.0005 * d, 7);
  pts.erase(std::remove_if(pts.begin(), pts.end(),
                           [&](const Vec<3>& p) { return p[2] > side * spacing; }),
            pts.end());
  std::mt19937 rng(1);
  std::shuffle(pts.begin(), pts.end(), rng);
  const int n = static_cast<int>(pts.size());
  Spheres<3, Space> beads(pts, 0.5 * d, rho);
  DemSolver<3, Space> dem(beads, box_walls<3>(lo, hi), LinearSpringDashpot<3>(k_n, 0.9, 0.2), lo,
                          hi, Vec<3>{{0, 0, -9.81}});
  const Real dt = dem.time_step();
  const int steps = 10;
  const auto ten_steps = [&] {
    for (int s = 0; s < steps; ++s) dem.step(dt);
  };
  const auto shuffled = bench::time_it<Space>(ten_steps, 1);
  const auto reorder = bench::time_it<Space>([&] { dem.reorder(); }, 1);
  const auto step = bench::time_it<Space>(ten_steps, 3);
  CellList<3, Space> cells(Grid<3>(lo, hi, 1.05 * d));  // as the solver bins
  const auto bin = bench::time_it<Space>([&] { cells.build(beads.x, n); }, 5);
  const double ns = 1e9 / n;
  Record r{Space::name(), Space().concurrency(), n};
  r.step_ns = step.median_s * ns / steps;
  r.step_min_ns = step.min_s * ns / steps;
  r.shuffled_step_ns = shuffled.median_s * ns / steps;
  r.bin_ns = bin.median_s * ns;
  r.reorder_ns = reorder.median_s * ns;
  r.contacts_per_bead = dem.contacts_per_bead();
  return r;
}

template <class Space>
void run_all(std::vector<Record>& out) {
  for (long n : {10000L, 100000L, 1000000L}) {
    out.push_back(run<Space>(n));
    const auto& r = out.back();
    fmt::print(stderr,
               "{} {}t n={}: {:.0f} ns/bead/step ({:.0f} unsorted, binning {:.0f}), "
               "{:.2f} contacts/bead\n",
               r.backend, r.threads, r.n, r.step_ns, r.shuffled_step_ns, r.bin_ns,
               r.contacts_per_bead);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  const std::string path = argc > 1 ? argv[1] : "dem_contacts.json";
  const bool serial = !(argc > 2 && std::string(argv[2]) == "--no-serial");
  std::vector<Record> records;
#ifdef KOKKOS_ENABLE_SERIAL
  if (serial) run_all<Kokkos::Serial>(records);
#endif
  run_all<Kokkos::DefaultExecutionSpace>(records);
  auto out = fmt::output_file(path);
  out.print("[\n");
  for (std::size_t i = 0; i < records.size(); ++i) {
    const auto& r = records[i];
    out.print(
        "  {{\"backend\": \"{}\", \"threads\": {}, \"n\": {}, \"step_ns_per_bead\": {:.1f}, "
        "\"step_ns_per_bead_best\": {:.1f}, \"unsorted_step_ns_per_bead\": {:.1f}, "
        "\"bin_ns_per_bead\": {:.1f}, \"reorder_ns_per_bead\": {:.1f}, \"contacts_per_bead\": "
        "{:.2f}}}{}\n",
        r.backend, r.threads, r.n, r.step_ns, r.step_min_ns, r.shuffled_step_ns, r.bin_ns,
        r.reorder_ns, r.contacts_per_bead, i + 1 < records.size() ? "," : "");
  }
  out.print("]\n");
  fmt::print("wrote {}\n", path);
}
