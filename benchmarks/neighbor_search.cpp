// Binning and one neighbour sweep (summation density), 2D and 3D, on the Serial and
// OpenMP backends; also a sweep through a stored CSR list, to measure which wins for
// loops repeated within one step. Writes JSON (one record per case) to argv[1];
// `--no-serial` skips the Serial cases (for a second run at another thread count).
#include "benchmarks/records.hpp"
#include "benchmarks/timer.hpp"
#include "kernels/cubic_spline.hpp"
#include "kernels/summation_density.hpp"
#include "src/backend.hpp"
#include "src/core/lattice.hpp"
#include "src/core/neighbor_list.hpp"
#include "src/core/reorder.hpp"

#include <fmt/core.h>

#include <cmath>
#include <string>
#include <vector>

using namespace dvisph;

namespace {

template <int D, class Space>
bench::Record run(long target_n) {
  using Mem = typename Space::memory_space;
  const Real dx = 1.0;
  const int side = static_cast<int>(std::round(std::pow(double(target_n), 1.0 / D)));
  Vec<D> lo, hi;
  for (int k = 0; k < D; ++k) lo[k] = 0, hi[k] = side * dx;
  // jittered lattice, then shuffled so binning and reordering have work to do
  auto pts = lattice<D>(lo, hi, dx, 0.1 * dx, 42);
  std::mt19937 rng(1);
  std::shuffle(pts.begin(), pts.end(), rng);
  const int n = static_cast<int>(pts.size());
  Kokkos::View<Real* [D], Mem> x("x", n);
  Kokkos::View<Real*, Mem> m("m", n), rho("rho", n);
  copy_points<D>(pts, x);
  Kokkos::deep_copy(m, 1.0);
  const CubicSpline<D> kernel(1.3 * dx);

  Vec<D> glo = lo, ghi = hi;
  for (int k = 0; k < D; ++k) glo[k] -= dx, ghi[k] += dx;
  CellList<D, Space> cells(Grid<D>(glo, ghi, kernel.radius()));
  const auto bin = bench::time_it<Space>([&] { cells.build(x, n); }, 5);

  // sweeps on particles sorted by cell, as the solver keeps them
  Kokkos::View<Real* [D], Mem> xs("xs", n);
  gather_rows<Space>(xs, x, cells.permutation());
  cells.build(xs, n);
  const CellSweep<D, Space> sweep(cells, xs, kernel.radius());
  const auto cell_sweep =
      bench::time_it<Space>([&] { summation_density<D>(sweep, kernel, xs, m, rho, n); }, 5);
  NeighborList<D, Space> list;
  // counted afresh (as after a reorder), then filled in place (as most steps)
  const auto list_build = bench::time_it<Space>([&] { list.forget_layout(); list.build(sweep, xs, n); }, 3);
  const auto list_refill = bench::time_it<Space>([&] { list.build(sweep, xs, n); }, 3);
  const auto list_sweep = bench::time_it<Space>(
      [&] { summation_density<D>(list.sweep(), kernel, xs, m, rho, n); }, 5);

  const double ns = 1e9 / n;
  fmt::print(stderr, "{} {}t {}D n={}: done\n", Space::name(), Space().concurrency(), D, n);
  return bench::Record()
      .add("backend", Space::name())
      .add("threads", Space().concurrency())
      .add("dim", D)
      .add("n", n)
      .add("bin_ns_per_particle", bin.median_s * ns, 2)
      .add("sweep_ns_per_particle", cell_sweep.median_s * ns, 2)
      .add("list_build_ns_per_particle", list_build.median_s * ns, 2)
      .add("list_refill_ns_per_particle", list_refill.median_s * ns, 2)
      .add("list_sweep_ns_per_particle", list_sweep.median_s * ns, 2)
      .add("pairs_per_particle", double(list.pairs()) / n, 1);
}

template <class Space>
void run_all(std::vector<bench::Record>& out) {
  for (long n : {10000L, 100000L, 1000000L}) {
    out.push_back(run<2, Space>(n));
    out.push_back(run<3, Space>(n));
  }
}

}  // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  const bool serial = !(argc > 2 && std::string(argv[2]) == "--no-serial");
  bench::run_on_backends(serial, argc > 1 ? argv[1] : "neighbor_search.json",
                         [](auto space, auto& records) { run_all<decltype(space)>(records); });
}
