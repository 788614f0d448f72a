// The pressure Poisson system of IsphSolver (solvers/isph/pressure_poisson.hpp) at the
// first step of a dam break, 2D and 3D, at about 1e4, 1e5 and 1e6 particles, on Serial
// and the default execution space:
//  - the mat-vec q = A p three ways: matrix-free over the cell lists (`cell`),
//    matrix-free over the stored neighbour list (`list`, the solver with
//    numerics.pressure_operator: matrix_free), and with the coefficients stored (`csr`,
//    the solver's default: solvers/isph/poisson_matrix.hpp);
//    each for one and for two right-hand sides;
//  - the solver's PCG with two right-hand sides against two single solves, and a single
//    solve with the stored coefficients;
//  - Eigen's CG (Jacobi preconditioner, as ours) on the assembled matrix against our PCG,
//    same tolerance, same initial guess, as many threads as the backend.
// The system: a water column a wide and 2a high (3D: a x a x 2a, a = 5 cm) in the corner of
// a tank 2a long (3D: 2a x a), fluid jittered by +-0.1 dx and sorted by cell as a run
// keeps it, at rest; the right-hand sides of the first step for gamma = 0.001 and 0.01, the
// pressure of still water as initial guess (a run warm-starts from the last pressure).
// The dam-break pressure differs from it near the free side, so CG needs more iterations
// than in a running simulation; compare times per iteration.
//
// Usage: bench_pressure_poisson OUT.json [--no-serial] [--max-n N] [--max-solve-n N]
// (skip systems above N particles; solve only systems up to N particles, default 2e5).
#include "benchmarks/records.hpp"
#include "benchmarks/timer.hpp"
#include "kernels/wendland_c2.hpp"
#include "solvers/isph/predictor.hpp"
#include "solvers/isph/free_surface.hpp"
#include "solvers/cell_multigrid.hpp"
#include "solvers/isph/poisson_matrix.hpp"
#include "src/core/neighbor_list.hpp"
#include "src/core/reorder.hpp"
#include "src/scene_particles.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

using namespace dvisph;

namespace {

constexpr Real column_width = 0.05, rho0 = 1000, g_abs = 9.81;
constexpr Real cg_tolerance = 1e-8;  // the scenes' default
constexpr int cg_max_iterations = 20000;

template <int D>
Scene dam_break_scene(Real dx) {
  const Real a = column_width;
  const std::string yaml =
      D == 2 ? fmt::format(
                   "dimension: 2\nend_time: 1\ngeometry:\n  spacing: {}\n"
                   "  tank: {{lo: [0, 0], hi: [{}, {}]}}\n  fluid: [{{lo: [0, 0], hi: [{}, {}]}}]\n",
                   dx, 2 * a, 2 * a, a, 2 * a)
             : fmt::format(
                   "dimension: 3\nend_time: 1\ngeometry:\n  spacing: {}\n"
                   "  tank: {{lo: [0, 0, 0], hi: [{}, {}, {}]}}\n"
                   "  fluid: [{{lo: [0, 0, 0], hi: [{}, {}, {}]}}]\n",
                   dx, 2 * a, a, 2 * a, a, a, 2 * a);
  return parse_scene(yaml);
}

// The spacing a / m with the smallest m whose scene has at least target_n particles.
template <int D>
Real spacing_for(long target_n) {
  const auto count = [](int m) {
    return static_cast<long>(scene_particles<D>(dam_break_scene<D>(column_width / m)).x.size());
  };
  int hi = 4;
  while (count(hi) < target_n) hi *= 2;
  int lo = hi / 2 + 1;
  while (lo < hi) {
    const int m = (lo + hi) / 2;
    if (count(m) < target_n) lo = m + 1;
    else hi = m;
  }
  return column_width / lo;
}

// Copies column k of `from` into the single column of `to`.
template <class Space, class V>
void copy_column(const V& to, const V& from, int k, int n) {
  Kokkos::parallel_for(
      "dvisph::bench::ppe::copy_column", Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i) { to(i, 0) = from(i, k); });
}

// A memory-bound reference: a(i) = b(i) + s c(i) over 3 x 160 MB.
template <class Space>
double triad_bytes_per_second() {
  const int n = 20000000;
  Kokkos::View<Real*, typename Space::memory_space> a("dvisph::bench::triad::a", n),
      b("dvisph::bench::triad::b", n), c("dvisph::bench::triad::c", n);
  Kokkos::deep_copy(b, 1.0);
  Kokkos::deep_copy(c, 2.0);
  const auto t = bench::time_it<Space>(
      [&] {
        Kokkos::parallel_for(
            "dvisph::bench::triad", Kokkos::RangePolicy<Space>(0, n),
            KOKKOS_LAMBDA(int i) { a(i) = b(i) + 0.5 * c(i); });
      },
      10);
  return 3.0 * sizeof(Real) * n / t.median_s;
}

struct Options {
  bool serial = true;
  long max_n = 1000000, max_solve_n = 200000;
};

template <int D, class Space>
bench::Record run(long target_n, const Options& opt, double triad) {
  using Mem = typename Space::memory_space;
  using Kernel = WendlandC2<D>;
  const Scene scene = dam_break_scene<D>(spacing_for<D>(target_n));
  auto init = scene_particles<D>(scene);
  const Real dx = scene.spacing, volume = std::pow(dx, D);
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> jitter(-0.1 * dx, 0.1 * dx);
  for (std::size_t i = 0; i < init.x.size(); ++i)
    if (init.kind[i] == Kind::fluid)
      for (int k = 0; k < D; ++k) init.x[i][k] += jitter(rng);
  const int n = static_cast<int>(init.x.size());
  const Kernel kernel(scene.h_over_dx * dx);
  Vec<D> g = Vec<D>::zero();
  g[D - 1] = -g_abs;

  Kokkos::View<Real* [D], Mem> x0("dvisph::bench::ppe::x_unsorted", n), x("dvisph::bench::ppe::x", n),
      v("dvisph::bench::ppe::v", n), vstar("dvisph::bench::ppe::vstar", n);
  Kokkos::View<Kind*, Mem> kind0("dvisph::bench::ppe::kind_unsorted", n), kind("dvisph::bench::ppe::kind", n);
  Kokkos::View<Real*, Mem> m("dvisph::bench::ppe::m", n), rho("dvisph::bench::ppe::rho", n),
      invariance("dvisph::bench::ppe::invariance", n),
      truncation("dvisph::bench::ppe::truncation", n), diag("dvisph::bench::ppe::diag", n);
  Kokkos::View<Role*, Mem> role("dvisph::bench::ppe::role", n);
  Kokkos::View<Real**, Mem> b("dvisph::bench::ppe::b", n, 2), guess("dvisph::bench::ppe::guess", n, 2),
      p2("dvisph::bench::ppe::p2", n, 2), q2("dvisph::bench::ppe::q2", n, 2),
      b1("dvisph::bench::ppe::b1", n, 1), p1("dvisph::bench::ppe::p1", n, 1),
      q1("dvisph::bench::ppe::q1", n, 1);
  copy_points<D>(init.x, x0);
  {
    auto h = Kokkos::create_mirror_view(kind0);
    for (int i = 0; i < n; ++i) h(i) = init.kind[i];
    Kokkos::deep_copy(kind0, h);
  }
  Kokkos::deep_copy(m, rho0 * volume);

  // sorted by cell, then the first step's stages up to the pressure system
  CellList<D, Space> cells(Grid<D>(init.domain_lo, init.domain_hi, kernel.radius()));
  cells.build(x0, n);
  gather_rows<Space>(x, x0, cells.permutation());
  gather_rows<Space>(kind, kind0, cells.permutation());
  cells.build(x, n);
  const CellSweep<D, Space> cell_sweep(cells, x, kernel.radius());
  NeighborList<D, Space> list;
  list.build(cell_sweep, x, n);
  const auto ref = support_reference<D>(kernel, dx, rho0);
  const Real full_diagonal = ref.laplacian;
  const SurfaceTest<D> test = surface_test<D>(scene, ref);
  // no last pressure yet: `guess` is still zero
  density_and_roles<D>(list.sweep(), kernel, x, m, kind, guess, ClearWater{}, volume, test, rho,
                       role, invariance, truncation, n);
  const Real dt = std::min(1e-3, 0.25 * std::sqrt(kernel.h / g_abs));  // IsphSolver's first dt
  predictor<D>(list.sweep(), kernel, x, v, kind, ClearWater{}, g, 0.0, true, volume, dt, vstar, n);
  const Real gamma[max_rhs] = {0.001, 0.01};
  using Ppe = PressurePoisson<D, typename NeighborList<D, Space>::Sweep, Kernel, decltype(x),
                              decltype(role)>;
  const auto walls = tank_walls<D>(scene);
  const Ppe ppe_list{list.sweep(), kernel, x, role, volume, full_diagonal, walls};
  const PressurePoisson<D, CellSweep<D, Space>, Kernel, decltype(x), decltype(role)> ppe_cell{
      cell_sweep, kernel, x, role, volume, full_diagonal, walls};
  ppe_list.assemble(vstar, rho, invariance, rho0, test.rho_ref, g, dt, gamma, diag, b, n);
  PoissonMatrix<Space> csr;
  const auto csr_build = bench::time_it<Space>(
      [&] { csr.build(ppe_list, n); }, 3);

  // still water, P = rho0 g (2a - z), on the unknown rows
  const Real top = 2 * column_width;
  Kokkos::parallel_for(
      "dvisph::bench::ppe::hydrostatic_guess", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        const Real p = unknown(role(i)) ? rho0 * g_abs * (top - x(i, D - 1)) : 0;
        guess(i, 0) = guess(i, 1) = p;
      });
  int unknowns = 0;
  Kokkos::parallel_reduce(
      "dvisph::bench::ppe::count_unknowns", Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i, int& c) { c += unknown(role(i)) ? 1 : 0; }, unknowns);

  // the three mat-vecs must agree (same pairs, same order)
  Kokkos::deep_copy(p2, guess);
  Kokkos::View<Real**, Mem> q_list("dvisph::bench::ppe::q_list", n, 2);
  ppe_list.apply(p2, q_list, diag, n);
  double worst = 0;
  for (int variant = 0; variant < 2; ++variant) {
    if (variant == 0) ppe_cell.apply(p2, q2, diag, n);
    else csr.apply(p2, q2, diag, n);
    double diff = 0, scale = 0;
    Kokkos::parallel_reduce(
        "dvisph::bench::ppe::compare", Kokkos::RangePolicy<Space>(0, n),
        KOKKOS_LAMBDA(int i, double& d) { d = math::max(d, math::abs(q2(i, 0) - q_list(i, 0))); },
        Kokkos::Max<double>(diff));
    Kokkos::parallel_reduce(
        "dvisph::bench::ppe::scale", Kokkos::RangePolicy<Space>(0, n),
        KOKKOS_LAMBDA(int i, double& s) { s = math::max(s, math::abs(q_list(i, 0))); },
        Kokkos::Max<double>(scale));
    worst = std::max(worst, diff / scale);
  }

  const int repeats = n > 200000 ? 3 : 10;
  copy_column<Space>(p1, guess, 0, n);
  auto time_matvec = [&](const char* region, auto&& apply) {
    Kokkos::Profiling::pushRegion(region);
    const auto t = bench::time_it<Space>(apply, repeats);
    Kokkos::Profiling::popRegion();
    return t.median_s * 1e9 / n;
  };
  const double cell1 = time_matvec("dvisph::bench::ppe::matvec_cell", [&] { ppe_cell.apply(p1, q1, diag, n); });
  const double list1 = time_matvec("dvisph::bench::ppe::matvec_list", [&] { ppe_list.apply(p1, q1, diag, n); });
  const double csr1 = time_matvec("dvisph::bench::ppe::matvec_csr", [&] { csr.apply(p1, q1, diag, n); });
  const double cell2 = time_matvec("dvisph::bench::ppe::matvec2_cell", [&] { ppe_cell.apply(p2, q2, diag, n); });
  const double list2 = time_matvec("dvisph::bench::ppe::matvec2_list", [&] { ppe_list.apply(p2, q2, diag, n); });
  const double csr2 = time_matvec("dvisph::bench::ppe::matvec2_csr", [&] { csr.apply(p2, q2, diag, n); });
  // bytes a CSR mat-vec must move at least: weights and columns, row offsets, diag, role,
  // p and q once
  const double csr_bytes = csr.nonzeros() * (sizeof(Real) + sizeof(int)) +
                           double(n) * (sizeof(int) + 3 * sizeof(Real) + sizeof(Role));

  bench::Record r;
  r.add("backend", Space::name())
      .add("threads", Space().concurrency())
      .add("dim", D)
      .add("n", n)
      .add("unknowns", unknowns)
      .add("dx", dx, 6)
      .add("pairs_per_particle", double(list.pairs()) / n, 1)
      .add("nonzeros_per_unknown", double(csr.nonzeros()) / unknowns + 1, 1)
      .add_significant("matvec_max_relative_difference", worst, 3)
      .add("matvec_cell_ns_per_particle", cell1, 2)
      .add("matvec_list_ns_per_particle", list1, 2)
      .add("matvec_csr_ns_per_particle", csr1, 2)
      .add("matvec2_cell_ns_per_particle", cell2, 2)
      .add("matvec2_list_ns_per_particle", list2, 2)
      .add("matvec2_csr_ns_per_particle", csr2, 2)
      .add("csr_build_ns_per_particle", csr_build.median_s * 1e9 / n, 2)
      .add("csr_bytes_per_second", csr_bytes / (csr1 * 1e-9 * n), 0)
      .add("triad_bytes_per_second", triad, 0);
  fmt::print(stderr, "{} {}t {}D n={} ({} unknowns): mat-vec cell {:.0f}, list {:.0f}, csr {:.0f} ns/particle\n",
             Space::name(), Space().concurrency(), D, n, unknowns, cell1, list1, csr1);
  if (n > opt.max_solve_n) return r;

  // solves: two right-hand sides at once, each alone, alone with stored coefficients
  const int solve_repeats = n > 20000 ? 1 : 3;
  ConjugateGradient<Space> cg2, cg1;
  CgResult two, single[2], stored;
  Kokkos::Profiling::pushRegion("dvisph::bench::ppe::solve_two_rhs");
  const auto t_two = bench::time_it<Space>(
      [&] {
        Kokkos::deep_copy(p2, guess);
        two = cg2.solve(ppe_list, diag, b, p2, n, cg_tolerance, cg_max_iterations);
      },
      solve_repeats);
  Kokkos::Profiling::popRegion();
  Kokkos::Profiling::pushRegion("dvisph::bench::ppe::solve_two_single");
  const auto t_singles = bench::time_it<Space>(
      [&] {
        for (int k = 0; k < 2; ++k) {
          copy_column<Space>(b1, b, k, n);
          copy_column<Space>(p1, guess, k, n);
          single[k] = cg1.solve(ppe_list, diag, b1, p1, n, cg_tolerance, cg_max_iterations);
        }
      },
      solve_repeats);
  Kokkos::Profiling::popRegion();
  // column 0 alone, solved by `cg` with `op`, timed under a profiling region
  const auto time_column0 = [&](const char* region, auto& cg, const auto& op, CgResult& out,
                                Preconditioner<Space>* m = nullptr) {
    Kokkos::Profiling::pushRegion(region);
    const auto t = bench::time_it<Space>(
        [&] {
          copy_column<Space>(b1, b, 0, n);
          copy_column<Space>(p1, guess, 0, n);
          out = cg.solve(op, diag, b1, p1, n, cg_tolerance, cg_max_iterations, 0, m);
        },
        solve_repeats);
    Kokkos::Profiling::popRegion();
    return t;
  };
  const auto t_csr = time_column0("dvisph::bench::ppe::solve_csr", cg1, csr, stored);
  // the same stored solve with the Chebyshev preconditioner (numerics.cg_preconditioner)
  ConjugateGradient<Space> cg_cheb;
  cg_cheb.chebyshev(3, 30);
  CgResult chebyshev;
  const auto t_cheb = time_column0("dvisph::bench::ppe::solve_csr_chebyshev3", cg_cheb, csr, chebyshev);
  // and with the cell multigrid (numerics.cg_preconditioner: multigrid), its set-up apart
  CellMultigrid<D, Space> multigrid(init.domain_lo, init.domain_hi, 0, dx, kernel.radius());
  const auto t_mg_build = bench::time_it<Space>([&] { multigrid.build(csr, diag, x, n, 1); }, solve_repeats);
  CgResult mg;
  const auto t_mg = time_column0("dvisph::bench::ppe::solve_csr_multigrid", cg1, csr, mg, &multigrid);
  // its additive form (additive_multigrid; the same set-up)
  using Multigrid = CellMultigrid<D, Space>;
  Multigrid additive(init.domain_lo, init.domain_hi, 0, dx, kernel.radius(), Multigrid::FineLevel::additive);
  additive.build(csr, diag, x, n, 1);
  CgResult mg_add;
  const auto t_mg_add =
      time_column0("dvisph::bench::ppe::solve_csr_additive_multigrid", cg1, csr, mg_add, &additive);
  // the single solve of column 0 alone, for the comparison with Eigen
  const auto t_one = time_column0("dvisph::bench::ppe::solve_single", cg1, ppe_list, single[0]);

  // Eigen: the same matrix (from the stored coefficients) over the unknown rows
  auto h_offsets = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), csr.offsets());
  auto h_columns = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), csr.columns());
  auto h_values = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), csr.values());
  auto h_diag = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), diag);
  auto h_b = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b);
  auto h_guess = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), guess);
  std::vector<int> index(n, -1);
  int rows = 0;
  for (int i = 0; i < n; ++i)
    if (h_diag(i) > 0) index[i] = rows++;
  std::vector<Eigen::Triplet<Real>> triplets;
  triplets.reserve(csr.nonzeros() + rows);
  Eigen::VectorXd rhs(rows), x_eigen0(rows);
  for (int i = 0; i < n; ++i) {
    if (index[i] < 0) continue;
    triplets.emplace_back(index[i], index[i], h_diag(i));
    for (int a = h_offsets(i); a < h_offsets(i + 1); ++a)
      triplets.emplace_back(index[i], index[h_columns(a)], h_values(a));
    rhs[index[i]] = h_b(i, 0);
    x_eigen0[index[i]] = h_guess(i, 0);
  }
  Eigen::SparseMatrix<Real, Eigen::RowMajor> A(rows, rows);
  A.setFromTriplets(triplets.begin(), triplets.end());
  // Eigen parallelizes CG with Lower|Upper on a row-major matrix through OpenMP
  const int eigen_threads = std::is_same_v<Mem, Kokkos::HostSpace> ? Space().concurrency()
                                                                     : Kokkos::DefaultHostExecutionSpace().concurrency();
  Eigen::setNbThreads(eigen_threads);
  Eigen::ConjugateGradient<decltype(A), Eigen::Lower | Eigen::Upper> eigen_cg;
  eigen_cg.setTolerance(cg_tolerance);
  eigen_cg.setMaxIterations(cg_max_iterations);
  eigen_cg.compute(A);
  Eigen::VectorXd x_eigen;
  const auto t_eigen = bench::time_it<Kokkos::DefaultHostExecutionSpace>(
      [&] { x_eigen = eigen_cg.solveWithGuess(rhs, x_eigen0); }, solve_repeats);
  auto h_p1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p1);
  double diff = 0, scale = 0;
  for (int i = 0; i < n; ++i)
    if (index[i] >= 0) {
      diff = std::max(diff, std::abs(h_p1(i, 0) - x_eigen[index[i]]));
      scale = std::max(scale, std::abs(x_eigen[index[i]]));
    }

  r.add_significant("cg_tolerance", cg_tolerance, 3)
      .add("solve_two_rhs_s", t_two.median_s, 4)
      .add("solve_two_rhs_iterations", two.iterations)
      .add("solve_two_single_s", t_singles.median_s, 4)
      .add("solve_single_iterations", single[0].iterations)
      .add("solve_single_iterations_gamma2", single[1].iterations)
      .add("solve_single_s", t_one.median_s, 4)
      .add("solve_csr_s", t_csr.median_s, 4)
      .add("solve_csr_iterations", stored.iterations)
      .add("solve_csr_chebyshev3_s", t_cheb.median_s, 4)
      .add("solve_csr_chebyshev3_iterations", chebyshev.iterations)
      .add("solve_csr_multigrid_s", t_mg.median_s, 4)
      .add("solve_csr_multigrid_iterations", mg.iterations)
      .add("solve_csr_additive_multigrid_s", t_mg_add.median_s, 4)
      .add("solve_csr_additive_multigrid_iterations", mg_add.iterations)
      .add("multigrid_build_s", t_mg_build.median_s, 4)
      .add("multigrid_levels", multigrid.levels())
      .add("eigen_s", t_eigen.median_s, 4)
      .add("eigen_iterations", static_cast<long>(eigen_cg.iterations()))
      .add("eigen_threads", eigen_threads)
      .add("eigen_over_ours", t_eigen.median_s / t_one.median_s, 3)
      .add_significant("eigen_max_relative_difference", diff / scale, 3);
  fmt::print(stderr,
             "  solve: two rhs {:.3f} s ({} it), two singles {:.3f} s ({} + {} it), csr {:.3f} s "
             "({} it; Chebyshev 3: {:.3f} s, {} it; multigrid {:.3f} s, {} it, {} levels, set-up {:.3f} s; "
             "additive {:.3f} s, {} it), Eigen {:.3f} s ({} it) = {:.2f} x ours ({:.3f} s)\n",
             t_two.median_s, two.iterations, t_singles.median_s, single[0].iterations,
             single[1].iterations, t_csr.median_s, stored.iterations, t_cheb.median_s,
             chebyshev.iterations, t_mg.median_s, mg.iterations, multigrid.levels(), t_mg_build.median_s,
             t_mg_add.median_s, mg_add.iterations, t_eigen.median_s, eigen_cg.iterations(),
             t_eigen.median_s / t_one.median_s, t_one.median_s);
  return r;
}

template <class Space>
void run_all(std::vector<bench::Record>& out, const Options& opt) {
  const double triad = triad_bytes_per_second<Space>();
  for (long n : {10000L, 100000L, 1000000L}) {
    if (n > opt.max_n) continue;
    out.push_back(run<2, Space>(n, opt, triad));
    out.push_back(run<3, Space>(n, opt, triad));
  }
}

}  // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  const std::string path = argc > 1 ? argv[1] : "pressure_poisson.json";
  Options opt;
  for (int a = 2; a < argc; ++a) {
    const std::string arg = argv[a];
    if (arg == "--no-serial") opt.serial = false;
    else if (arg == "--max-n" && a + 1 < argc) opt.max_n = std::stol(argv[++a]);
    else if (arg == "--max-solve-n" && a + 1 < argc) opt.max_solve_n = std::stol(argv[++a]);
    else {
      fmt::print(stderr, "unknown argument {}\n", arg);
      return 2;
    }
  }
  bench::run_on_backends(opt.serial, path, [&](auto space, auto& records) {
    run_all<decltype(space)>(records, opt);
  });
}
