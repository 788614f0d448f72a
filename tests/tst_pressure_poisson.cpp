// The PCG on the pressure Poisson system, matrix-free and with the stored matrix, gives
// the same pressure as Eigen's ConjugateGradient on the assembled sparse matrix, for two
// right-hand sides at once, on disordered particles with walls and a free surface.
#include "kernels/cubic_spline.hpp"
#include "solvers/isph/free_surface.hpp"
#include "solvers/isph/poisson_matrix.hpp"
#include "src/neighbor_list.hpp"
#include "src/scene_particles.hpp"
#include "tests/test_space.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <catch2/catch.hpp>

#include <random>

using namespace dvisph;
using Mem = TestSpace::memory_space;

TEST_CASE("PCG, matrix-free and stored, equals Eigen's CG on the assembled PPE", "[pressure_poisson]") {
  constexpr int D = 2;
  const Scene scene = parse_scene(R"(
dimension: 2
end_time: 1
geometry:
  spacing: 0.01
  tank: {lo: [0, 0], hi: [0.3, 0.3]}
  fluid: [{lo: [0, 0], hi: [0.2, 0.15]}]
)");
  auto init = scene_particles<D>(scene);
  // disorder the fluid
  std::mt19937 rng(3);
  std::uniform_real_distribution<Real> u(-0.1 * scene.spacing, 0.1 * scene.spacing);
  for (std::size_t i = 0; i < init.x.size(); ++i)
    if (init.kind[i] == Kind::fluid)
      for (int k = 0; k < D; ++k) init.x[i][k] += u(rng);
  const int n = static_cast<int>(init.x.size());
  const Real dx = scene.spacing, volume = dx * dx, rho0 = 1000, dt = 1e-3;
  const CubicSpline<D> kernel(1.3 * dx);

  Kokkos::View<Real* [D], Mem> x("x", n), vstar("vstar", n);
  Kokkos::View<Kind*, Mem> kind("kind", n);
  Kokkos::View<Real*, Mem> m("m", n), rho("rho", n), invariance("invariance", n),
      truncation("truncation", n), diag("diag", n);
  Kokkos::View<Role*, Mem> role("role", n);
  copy_points<D>(init.x, x);
  {
    auto hk = Kokkos::create_mirror_view(kind);
    auto hv = Kokkos::create_mirror_view(vstar);
    for (int i = 0; i < n; ++i) {
      hk(i) = init.kind[i];
      for (int k = 0; k < D; ++k) hv(i, k) = 0.1 * u(rng) / dx;
    }
    Kokkos::deep_copy(kind, hk);
    Kokkos::deep_copy(vstar, hv);
  }
  Kokkos::deep_copy(m, rho0 * volume);

  CellList<D, TestSpace> cells(Grid<D>(init.domain_lo, init.domain_hi, kernel.radius()));
  cells.build(x, n);
  NeighborList<D, TestSpace> list;
  list.build(CellSweep<D, TestSpace>(cells, x, kernel.radius()), x, n);
  Kokkos::View<Real**, Mem> b("b", n, 2), p("p", n, 2);
  const auto ref = support_reference<D>(kernel, dx, rho0);
  const SurfaceTest<D> test = surface_test<D>(scene, ref);
  density_and_roles<D>(list.sweep(), kernel, x, m, kind, p, ClearWater{}, volume, test, rho, role,
                       invariance, truncation, n);

  using PPE = PressurePoisson<D, NeighborList<D, TestSpace>::Sweep, CubicSpline<D>, decltype(x),
                              decltype(role)>;
  const PPE ppe{list.sweep(), kernel, x, role, volume, ref.laplacian, tank_walls<D>(scene)};
  const Real gamma[max_rhs] = {0.0, 0.5};
  ppe.assemble(vstar, rho, invariance, rho0, ref.rho, Vec<D>{{0, -9.81}}, dt, gamma, diag, b, n);
  ConjugateGradient<TestSpace> cg;
  const auto result = cg.solve(ppe, diag, b, p, n, 1e-12, 5000);
  REQUIRE(result.converged);
  // the stored matrix applies the same sums in the same order: the same bits
  PoissonMatrix<TestSpace> matrix;
  matrix.build(ppe, n);
  Kokkos::View<Real**, Mem> q_free("q_free", n, 2), q_stored("q_stored", n, 2),
      p_stored("p_stored", n, 2);
  ppe.apply(p, q_free, diag, n);
  matrix.apply(p, q_stored, diag, n);
  int differ = 0;
  Kokkos::parallel_reduce(
      "test::compare", Kokkos::RangePolicy<TestSpace>(0, n),
      KOKKOS_LAMBDA(int i, int& c) { c += q_free(i, 0) != q_stored(i, 0) || q_free(i, 1) != q_stored(i, 1); },
      differ);
  CHECK(differ == 0);
  const auto stored = cg.solve(matrix, diag, b, p_stored, n, 1e-12, 5000);
  REQUIRE(stored.converged);
  CHECK(stored.iterations == result.iterations);

  // assemble the same system on the host by brute force over pairs
  auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), x);
  auto hrole = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), role);
  auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b);
  auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p);
  auto hp_stored = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_stored);
  std::vector<int> index(n, -1);
  int rows = 0;
  for (int i = 0; i < n; ++i)
    if (unknown(hrole(i))) index[i] = rows++;
  REQUIRE(rows > 100);
  int surface = 0;
  for (int i = 0; i < n; ++i) surface += hrole(i) == Role::surface;
  REQUIRE(surface > 10);
  std::vector<Eigen::Triplet<Real>> triplets;
  for (int i = 0; i < n; ++i) {
    if (index[i] < 0) continue;
    Real d = 0;
    for (int j = 0; j < n; ++j) {
      if (j == i || !in_stencil(hrole(j))) continue;
      Real r2 = 0;
      for (int k = 0; k < D; ++k) r2 += (hx(i, k) - hx(j, k)) * (hx(i, k) - hx(j, k));
      if (r2 >= kernel.radius() * kernel.radius()) continue;
      const Real w = laplacian_weight<D>(kernel, std::sqrt(r2), volume);
      d -= w;
      if (index[j] >= 0) triplets.emplace_back(index[i], index[j], w);
    }
    // the ghost air of the free surface (not on walls)
    const Real air = hrole(i) == Role::wall ? 0 : 2 * std::max(0.0, ref.laplacian - d);
    triplets.emplace_back(index[i], index[i], d + air);
  }
  Eigen::SparseMatrix<Real> A(rows, rows);
  A.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::ConjugateGradient<Eigen::SparseMatrix<Real>, Eigen::Lower | Eigen::Upper> eigen_cg;
  eigen_cg.setTolerance(1e-13);
  eigen_cg.setMaxIterations(20000);
  eigen_cg.compute(A);
  for (int c = 0; c < 2; ++c) {
    Eigen::VectorXd rhs(rows);
    for (int i = 0; i < n; ++i)
      if (index[i] >= 0) rhs[index[i]] = hb(i, c);
    const Eigen::VectorXd ref = eigen_cg.solve(rhs);
    REQUIRE(eigen_cg.info() == Eigen::Success);
    Real diff = 0, diff_stored = 0;
    for (int i = 0; i < n; ++i)
      if (index[i] >= 0) {
        diff = std::max(diff, std::abs(hp(i, c) - ref[index[i]]));
        diff_stored = std::max(diff_stored, std::abs(hp_stored(i, c) - ref[index[i]]));
      }
    const Real rel = diff / ref.cwiseAbs().maxCoeff();
    const Real rel_stored = diff_stored / ref.cwiseAbs().maxCoeff();
    WARN("column " << c << ": " << rows << " unknowns, PCG " << result.iterations
                   << " iterations, max |PCG - Eigen| / max |P| = " << rel << " (stored matrix: "
                   << rel_stored << ")");
    CHECK(rel < 1e-8);
    CHECK(rel_stored < 1e-8);
  }
}
