// The PCG on the pressure Poisson system, matrix-free and with the stored matrix, gives
// the same pressure as Eigen's ConjugateGradient on the assembled sparse matrix, for two
// right-hand sides at once, on disordered particles with walls and a free surface.
#include "kernels/cubic_spline.hpp"
#include "kernels/wendland_c2.hpp"
#include "solvers/isph/free_surface.hpp"
#include "solvers/cell_multigrid.hpp"
#include "solvers/isph/poisson_matrix.hpp"
#include "src/core/neighbor_list.hpp"
#include "src/scene_particles.hpp"
#include "tests/test_space.hpp"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <catch2/catch.hpp>

#include <random>

using namespace dvisph;
using Mem = TestSpace::memory_space;

namespace {
// The PPE's inputs for a 2D scene's particles at the given positions, with v* given
// per particle: the neighbour list (cells over the box lo..hi), summation density,
// roles, invariance weights and the lattice references.
template <class Kernel>
struct PpeInputs {
  static constexpr int D = 2;
  using Points = std::vector<std::array<Real, D>>;
  Kernel kernel;
  int n;
  Real volume, rho0;
  Kokkos::View<Real* [D], Mem> x, vstar;
  Kokkos::View<Kind*, Mem> kind;
  Kokkos::View<Real*, Mem> m, rho, weight, truncation, diag;
  Kokkos::View<Role*, Mem> role;
  CellList<D, TestSpace> cells;
  NeighborList<D, TestSpace> list;
  SupportReference<D> ref;

  PpeInputs(const Scene& scene, const Kernel& k, const Points& points, const std::vector<Kind>& kinds,
            const Points& velocities, const Vec<D>& lo, const Vec<D>& hi)
      : kernel(k),
        n(static_cast<int>(points.size())),
        volume(scene.spacing * scene.spacing),
        rho0(scene.density),
        x("x", n),
        vstar("vstar", n),
        kind("kind", n),
        m("m", n),
        rho("rho", n),
        weight("weight", n),
        truncation("truncation", n),
        diag("diag", n),
        role("role", n),
        cells(Grid<D>(lo, hi, k.radius())),
        ref(support_reference<D>(k, scene.spacing, scene.density)) {
    auto hx = Kokkos::create_mirror_view(x);
    auto hv = Kokkos::create_mirror_view(vstar);
    auto hk = Kokkos::create_mirror_view(kind);
    for (int i = 0; i < n; ++i) {
      hk(i) = kinds[i];
      for (int c = 0; c < D; ++c) hx(i, c) = points[i][c], hv(i, c) = velocities[i][c];
    }
    Kokkos::deep_copy(x, hx);
    Kokkos::deep_copy(vstar, hv);
    Kokkos::deep_copy(kind, hk);
    Kokkos::deep_copy(m, rho0 * volume);
    cells.build(x, n);
    list.build(CellSweep<D, TestSpace>(cells, x, kernel.radius()), x, n);
    const Kokkos::View<Real**, Mem> no_pressure("p", n, 1);  // last step's: none yet
    density_and_roles<D>(list.sweep(), kernel, x, m, kind, no_pressure, ClearWater{}, volume,
                         surface_test<D>(scene, ref), rho, role, weight, truncation, n);
  }

  using Ppe = PressurePoisson<D, typename NeighborList<D, TestSpace>::Sweep, Kernel,
                              Kokkos::View<Real* [D], Mem>, Kokkos::View<Role*, Mem>>;
  Ppe ppe(const TankWalls<D>& walls) const {
    return {list.sweep(), kernel, x, role, volume, ref.laplacian, walls};
  }
};
}  // namespace

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
  const Real dx = scene.spacing, dt = 1e-3;
  PpeInputs<CubicSpline<D>>::Points points, velocities;
  for (const auto& xi : init.x) points.push_back({xi[0], xi[1]});
  for (std::size_t i = 0; i < init.x.size(); ++i) {
    const Real vx = 0.1 * u(rng) / dx, vy = 0.1 * u(rng) / dx;
    velocities.push_back({vx, vy});
  }
  const PpeInputs<CubicSpline<D>> in(scene, CubicSpline<D>(1.3 * dx), points, init.kind, velocities,
                                     init.domain_lo, init.domain_hi);
  const int n = in.n;
  const auto& x = in.x;
  const auto& role = in.role;
  const auto& diag = in.diag;
  const auto& kernel = in.kernel;
  const auto& ref = in.ref;
  const Real volume = in.volume;
  Kokkos::View<Real**, Mem> b("b", n, 2), p("p", n, 2);
  const auto ppe = in.ppe(tank_walls<D>(scene));
  const Real gamma[max_rhs] = {0.0, 0.5};
  ppe.assemble(in.vstar, in.rho, in.weight, in.rho0, ref.rho, Vec<D>{{0, -9.81}}, dt, gamma, diag, b, n);
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
    // the ghost air of the free surface (not on walls; numerics.ghost_air: everywhere)
    const Real air = hrole(i) == Role::wall ? 0 : 2 * std::max(0.0, ref.laplacian - d);
    triplets.emplace_back(index[i], index[i], d + air);
  }
  Eigen::SparseMatrix<Real> A(rows, rows);
  A.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::ConjugateGradient<Eigen::SparseMatrix<Real>, Eigen::Lower | Eigen::Upper> eigen_cg;
  eigen_cg.setTolerance(1e-13);
  eigen_cg.setMaxIterations(20000);
  eigen_cg.compute(A);
  std::vector<Eigen::VectorXd> eigen_p;
  for (int c = 0; c < 2; ++c) {
    Eigen::VectorXd rhs(rows);
    for (int i = 0; i < n; ++i)
      if (index[i] >= 0) rhs[index[i]] = hb(i, c);
    const Eigen::VectorXd ref = eigen_cg.solve(rhs);
    eigen_p.push_back(ref);
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

  // The absolute stop (the solver's numerics.cg_density_tolerance): CG stops at the
  // first iteration where no row's |b - A p| exceeds it, and reports that maximum.
  Real b_max = 0;
  for (int i = 0; i < n; ++i) b_max = std::max({b_max, std::abs(hb(i, 0)), std::abs(hb(i, 1))});
  const Real limit = 1e-4 * b_max;
  Kokkos::View<Real**, Mem> p_abs("p_abs", n, 2), q_abs("q_abs", n, 2);
  const auto loose = cg.solve(matrix, diag, b, p_abs, n, 1e-14, 5000, limit);
  REQUIRE(loose.converged);
  CHECK(loose.iterations < result.iterations);
  matrix.apply(p_abs, q_abs, diag, n);
  auto hq = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), q_abs);
  auto hdiag = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), diag);
  for (int c = 0; c < 2; ++c) {
    Real worst = 0;
    for (int i = 0; i < n; ++i)
      if (hdiag(i) > 0) worst = std::max(worst, std::abs(hb(i, c) - hq(i, c)));
    WARN("column " << c << ": stopped after " << loose.iterations << " iterations at max |r| = "
                   << worst << " (limit " << limit << ")");
    CHECK(worst < limit * (1 + 1e-6));
    CHECK(loose.max_residual[c] == Approx(worst).epsilon(1e-6));
  }
  // one iteration fewer would not have met it: the loose solve with one iteration less
  Kokkos::View<Real**, Mem> p_short("p_short", n, 2);
  const auto shorter = cg.solve(matrix, diag, b, p_short, n, 1e-14, loose.iterations - 1, limit);
  CHECK_FALSE(shorter.converged);

  // Another preconditioner must give Eigen's pressure in fewer iterations than Jacobi's
  // (fewer than half, or for the additive multigrid, which trades iterations for matrix
  // applications, fewer), and be symmetric positive definite, as CG needs: x.My = y.Mx and x.Mx > 0 for random
  // x, y on the unknowns (columns 0 and 1 of xy; `precondition(xy, mxy)` applies M).
  Kokkos::View<Real**, Mem> xy("xy", n, 2), mxy("mxy", n, 2), scratch("scratch", n, 2);
  auto hxy = Kokkos::create_mirror_view(xy);
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 2; ++c) hxy(i, c) = index[i] >= 0 ? u(rng) : 0;
  Kokkos::deep_copy(xy, hxy);
  const auto check_preconditioner = [&](const char* name, const CgResult& solved,
                                        const Kokkos::View<Real**, Mem>& p_solved, auto&& precondition,
                                        int at_most) {
    REQUIRE(solved.converged);
    WARN(name << ": " << solved.iterations << " iterations against Jacobi's " << result.iterations);
    CHECK(solved.iterations <= at_most);
    auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p_solved);
    for (int c = 0; c < 2; ++c) {
      Real diff = 0;
      for (int i = 0; i < n; ++i)
        if (index[i] >= 0) diff = std::max(diff, std::abs(hp(i, c) - eigen_p[c][index[i]]));
      CHECK(diff / eigen_p[c].cwiseAbs().maxCoeff() < 1e-8);
    }
    precondition(xy, mxy);
    auto hm = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mxy);
    Real x_my = 0, y_mx = 0, x_mx = 0, norm = 0;
    for (int i = 0; i < n; ++i) {
      x_my += hxy(i, 0) * hm(i, 1);
      y_mx += hxy(i, 1) * hm(i, 0);
      x_mx += hxy(i, 0) * hm(i, 0);
      norm += std::abs(hxy(i, 0) * hm(i, 1));
    }
    CHECK(std::abs(x_my - y_mx) < 1e-12 * norm);
    CHECK(x_mx > 0);
  };

  // The Chebyshev preconditioner (numerics.cg_preconditioner: chebyshev)
  ConjugateGradient<TestSpace> chebyshev;
  chebyshev.chebyshev(4, 30);
  Kokkos::View<Real**, Mem> p_cheb("p_cheb", n, 2);
  check_preconditioner("Chebyshev (degree 4)", chebyshev.solve(matrix, diag, b, p_cheb, n, 1e-12, 5000),
                       p_cheb, [&](const auto& in, const auto& out) {
                         chebyshev.precondition(matrix, diag, in, out, scratch, n);
                       }, result.iterations / 2 - 1);

  // The cell multigrid (numerics.cg_preconditioner: multigrid, additive_multigrid)
  using Multigrid = CellMultigrid<D, TestSpace>;
  for (const auto fine : {Multigrid::FineLevel::smoothed, Multigrid::FineLevel::additive}) {
    Multigrid multigrid(init.domain_lo, init.domain_hi, 0, dx, kernel.radius(), fine);
    multigrid.build(matrix, diag, x, n, 2);
    CHECK(multigrid.levels() >= 2);
    Kokkos::View<Real**, Mem> p_mg("p_mg", n, 2);
    const bool smoothed = fine == Multigrid::FineLevel::smoothed;
    check_preconditioner(smoothed ? "multigrid" : "additive multigrid",
                         cg.solve(matrix, diag, b, p_mg, n, 1e-12, 5000, 0, &multigrid), p_mg,
                         [&](const auto& in, const auto& out) { multigrid.apply(in, out, scratch, n); },
                         smoothed ? result.iterations / 2 - 1 : result.iterations - 1);
  }
}

// eq. 5's sources, checked against what they must be, not against assemble itself
namespace {
struct Assembled {
  std::vector<std::array<Real, 2>> x;
  std::vector<Kind> kind;
  std::vector<Role> role;
  std::vector<Real> b, weight, rho;
  Real div_r_ref, rho_ref;
};

// A still-water tank (lattice, spacing stretched by `stretch` about the origin), v* =
// velocity(x) for fluid particles and 0 for walls, gravity g: the PPE's right-hand side
// for gamma.
template <class Velocity>
Assembled assemble_tank(Real stretch, Real gamma, Vec<2> g, Velocity velocity) {
  constexpr int D = 2;
  const Scene scene = parse_scene(R"(
dimension: 2
end_time: 1
geometry:
  spacing: 0.01
  tank: {lo: [0, 0], hi: [0.3, 0.3]}
  fluid: [{lo: [0, 0], hi: [0.3, 0.2]}]
)");
  const auto init = scene_particles<D>(scene);
  const Real dt = 1e-3;
  Assembled a;
  PpeInputs<WendlandC2<D>>::Points points, velocities;
  for (std::size_t i = 0; i < init.x.size(); ++i) {
    const std::array<Real, 2> xi{stretch * init.x[i][0], stretch * init.x[i][1]};
    points.push_back(xi);
    velocities.push_back(init.kind[i] == Kind::fluid ? velocity(xi) : std::array<Real, 2>{0, 0});
    a.x.push_back(xi);
    a.kind.push_back(init.kind[i]);
  }
  Vec<D> lo = init.domain_lo, hi = init.domain_hi;
  for (int k = 0; k < D; ++k) lo[k] *= 1.2, hi[k] *= 1.2;
  const PpeInputs<WendlandC2<D>> in(scene, WendlandC2<D>(scene.h_over_dx * scene.spacing), points,
                                    init.kind, velocities, lo, hi);
  const int n = in.n;
  auto walls = tank_walls<D>(scene);
  for (int k = 0; k < D; ++k) walls.lo[k] *= stretch, walls.hi[k] *= stretch;
  Kokkos::View<Real**, Mem> b("b", n, 1);
  const Real gam[max_rhs] = {gamma, gamma};
  in.ppe(walls).assemble(in.vstar, in.rho, in.weight, in.rho0, in.ref.rho, g, dt, gam, in.diag, b, n);
  auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b);
  auto hr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), in.role);
  auto hw = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), in.weight);
  auto hrho = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), in.rho);
  for (int i = 0; i < n; ++i) {
    a.b.push_back(hb(i, 0));
    a.role.push_back(hr(i));
    a.weight.push_back(hw(i));
    a.rho.push_back(hrho(i));
  }
  a.div_r_ref = in.ref.div_r;
  a.rho_ref = in.ref.rho;
  return a;
}

// a fluid particle whose support lies in the water's interior (3 spacings from its
// faces and from the walls)
bool deep_inside(const std::array<Real, 2>& x, Real stretch) {
  const Real dx = 0.01 * stretch, margin = 3.5 * dx;
  return x[0] > margin && x[0] < 0.3 * stretch - margin && x[1] > margin && x[1] < 0.2 * stretch - margin;
}
}  // namespace

TEST_CASE("assemble: a linear v* gives -(rho0/dt) tr grad v*", "[pressure_poisson]") {
  // v* = A x with tr A = 0.3 - 0.1 and a shear; on a square lattice
  // sum_j V (v_j - v_i).grad W_ij = tr A div_r_ref / D exactly (lattice symmetry)
  const Real a11 = 0.3, a12 = 0.7, a21 = -0.2, a22 = -0.1, rho0 = 1000, dt = 1e-3;
  const auto a = assemble_tank(1.0, 0.0, Vec<2>{{0, 0}}, [&](const std::array<Real, 2>& x) {
    return std::array<Real, 2>{a11 * x[0] + a12 * x[1], a21 * x[0] + a22 * x[1]};
  });
  const Real expected = -(rho0 / dt) * (a11 + a22) * a.div_r_ref / 2;
  CHECK(a.div_r_ref / 2 == Approx(1).epsilon(0.01));  // the lattice's div r of x is about D
  int checked = 0;
  for (std::size_t i = 0; i < a.b.size(); ++i) {
    if (a.kind[i] != Kind::fluid || !deep_inside(a.x[i], 1.0)) continue;
    ++checked;
    CHECK(a.b[i] == Approx(expected).epsilon(1e-9));
  }
  CHECK(checked > 100);
}

TEST_CASE("assemble: uniform compression and expansion give exactly the gamma term", "[pressure_poisson]") {
  // v* = 0: only gamma rho0 (1 - <rho>/rho_ref) / dt^2 is left, <rho> the lattice sum at the
  // stretched spacing with the same masses, and the weight 1 in the interior either way
  const Real rho0 = 1000, dt = 1e-3, gamma = 0.5, dx = 0.01;
  for (const Real stretch : {0.97, 1.04}) {
    const auto a = assemble_tank(stretch, gamma, Vec<2>{{0, 0}},
                                 [](const std::array<Real, 2>&) { return std::array<Real, 2>{0, 0}; });
    const WendlandC2<2> kernel(1.5 * dx);
    const Real rho = support_reference<2>(kernel, stretch * dx, rho0 / (stretch * stretch)).rho;
    const Real expected = -gamma * rho0 * (1 - rho / a.rho_ref) / (dt * dt);
    int checked = 0;
    for (std::size_t i = 0; i < a.b.size(); ++i) {
      if (a.kind[i] != Kind::fluid || !deep_inside(a.x[i], stretch)) continue;
      ++checked;
      INFO("stretch " << stretch);
      CHECK(a.weight[i] == 1);
      CHECK(a.b[i] == Approx(expected).epsilon(1e-9));
    }
    CHECK(checked > 100);
    CHECK((stretch < 1 ? expected > 0 : expected < 0));  // compression pushes apart
  }
}

TEST_CASE("assemble: a wall row pushes only on water moving into it", "[pressure_poisson]") {
  // water moving right into the right wall: that wall's rows change, the left wall's
  // do not; moving left, the reverse. No gravity: the hydrostatic part is 0.
  const auto still = assemble_tank(1.0, 0.0, Vec<2>{{0, 0}},
                                   [](const std::array<Real, 2>&) { return std::array<Real, 2>{0, 0}; });
  const auto right = assemble_tank(1.0, 0.0, Vec<2>{{0, 0}},
                                   [](const std::array<Real, 2>&) { return std::array<Real, 2>{0.1, 0}; });
  const auto left = assemble_tank(1.0, 0.0, Vec<2>{{0, 0}},
                                  [](const std::array<Real, 2>&) { return std::array<Real, 2>{-0.1, 0}; });
  int pushed_right = 0, pushed_left = 0, side_rows = 0;
  for (std::size_t i = 0; i < still.b.size(); ++i) {
    if (still.role[i] != Role::wall || still.x[i][1] < 0.05 || still.x[i][1] > 0.15) continue;
    ++side_rows;
    CHECK(still.b[i] == 0);
    if (still.x[i][0] > 0.3) {  // right wall
      pushed_right += right.b[i] != 0;
      CHECK(right.b[i] >= 0);  // A P = b, A = -L positive definite: b > 0 raises the wall's P
      CHECK(left.b[i] == 0);
    } else if (still.x[i][0] < 0) {
      pushed_left += left.b[i] != 0;
      CHECK(left.b[i] >= 0);
      CHECK(right.b[i] == 0);
    }
  }
  CHECK(side_rows > 20);
  CHECK(pushed_right > 10);
  CHECK(pushed_left > 10);
}

TEST_CASE("wall normals: the tank's faces, its corners and the gate", "[pressure_poisson]") {
  const Scene s = parse_scene(R"(
dimension: 2
end_time: 1
geometry:
  spacing: 0.01
  tank: {lo: [0, 0], hi: [0.4, 0.3]}
  fluid: [{lo: [0, 0], hi: [0.1, 0.2]}]
  gate: {x: 0.1, remove_at: 0.5}
)");
  auto walls = tank_walls<2>(s);
  const auto n = [&](Real x, Real y) { return walls.inward_normal(Vec<2>{{x, y}}); };
  CHECK(n(-0.005, 0.1)[0] == 1);     // left wall
  CHECK(n(0.2, -0.005)[1] == 1);     // floor
  CHECK(n(-0.005, -0.005)[0] == Approx(std::sqrt(0.5)));  // corner: the diagonal
  CHECK(n(0.105, 0.1)[0] == -1);     // the gate, toward the water behind it
  CHECK(n(0.105, 0.1)[1] == 0);
  CHECK(n(0.05, 0.1)[0] == 0);       // inside the tank, upstream of the gate: none
  walls.gate = false;                // removed
  CHECK(n(0.105, 0.1)[0] == 0);
}
