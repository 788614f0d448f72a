// Cost of a DEM step (kick-drift, the Verlet list's check and, when due, its rebuild,
// contact forces with history, kick) per bead, for the paper's glass beads in a dense bed
// in a box, at 1e4, 1e5 and 1e6 beads, on Serial and the default execution space. Beads
// at rest rarely need a rebuild: the figure is the step between rebuilds (before
// 2026-12-01 it binned every step). Also the binning alone (part of a list rebuild),
// a reorder by cell, and steps before it, on beads shuffled in memory. Writes JSON (one
// record per case) to argv[1]; `--no-serial` skips the Serial cases (for a second run
// at another thread count).
//
// The bed: a simple cubic lattice compressed to 0.998 d with +-0.0005 d jitter, at rest
// under gravity, shuffled in memory, then reordered by cell as a run would keep it.
// Every bead presses on its 6 lattice neighbours (overlaps of about 5 um), the
// coordination of a dense random packing; the solid fraction is 0.52 against about 0.6
// for random close packing, so the sweep meets about 15 % fewer non-touching candidates.
#include "benchmarks/records.hpp"
#include "benchmarks/timer.hpp"
#include "solvers/dem/dem_solver.hpp"
#include "src/core/lattice.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace dvisph;
using namespace dvisph::dem;

namespace {

template <class Space>
bench::Record run(long target_n) {
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
  const double ns = 1e9 / n, contacts = dem.contacts_per_bead();
  fmt::print(stderr,
             "{} {}t n={}: {:.0f} ns/bead/step ({:.0f} unsorted, binning {:.0f}), "
             "{:.2f} contacts/bead\n",
             Space::name(), Space().concurrency(), n, step.median_s * ns / steps,
             shuffled.median_s * ns / steps, bin.median_s * ns, contacts);
  return bench::Record()
      .add("backend", Space::name())
      .add("threads", Space().concurrency())
      .add("n", n)
      .add("step_ns_per_bead", step.median_s * ns / steps, 1)
      .add("step_ns_per_bead_best", step.min_s * ns / steps, 1)
      .add("unsorted_step_ns_per_bead", shuffled.median_s * ns / steps, 1)
      .add("bin_ns_per_bead", bin.median_s * ns, 1)
      .add("reorder_ns_per_bead", reorder.median_s * ns, 1)
      .add("contacts_per_bead", contacts, 2);
}

template <class Space>
void run_all(std::vector<bench::Record>& out) {
  for (long n : {10000L, 100000L, 1000000L}) out.push_back(run<Space>(n));
}

}  // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  const bool serial = !(argc > 2 && std::string(argv[2]) == "--no-serial");
  bench::run_on_backends(serial, argc > 1 ? argv[1] : "dem_contacts.json",
                         [](auto space, auto& records) { run_all<decltype(space)>(records); });
}
