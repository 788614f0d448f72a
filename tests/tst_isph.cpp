// Stabilized ISPH, short versions of the validation runs (the full ones are in
// scripts/validate.sh): a hydrostatic tank and a dam break against Martin & Moyce.
#include "kernels/wendland_c2.hpp"
#include "solvers/isph/isph_solver.hpp"
#include "src/metrics.hpp"
#include "tests/test_space.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace dvisph;

namespace {
double deepest_in_walls(const IsphSolver<2, WendlandC2<2>, TestSpace>& s, const TankWalls<2>& walls) {
  return wall_penetration<2, TestSpace>(s.particles().x, s.particles().kind, s.size(), walls);
}

std::vector<std::string> stage_names(const IsphSolver<2, WendlandC2<2>, TestSpace>& s) {
  std::vector<std::string> names;
  for (const auto& st : s.stages()) names.push_back(st.name);
  return names;
}
const char* tank_2d = R"(
dimension: 2
end_time: 1
material: {kinematic_viscosity: 0}
geometry:
  spacing: 0.005
  tank: {lo: [0, 0], hi: [0.1, 0.15]}
  fluid: [{lo: [0, 0], hi: [0.1, 0.1]}]
metrics: {kind: hydrostatic, water_height: 0.1}
)";
}  // namespace

TEST_CASE("a scene runs only the stages it needs", "[isph]") {
  const Scene inviscid = parse_scene(tank_2d);
  IsphSolver<2, WendlandC2<2>, TestSpace> a(inviscid);
  CHECK(stage_names(a) == std::vector<std::string>{"reorder", "neighbors", "density_and_roles",
                                                   "predictor", "pressure_poisson", "corrector",
                                                   "move"});
  const Scene viscous_gate = parse_scene(tank_2d, {"material.kinematic_viscosity=1e-6",
                                                   "geometry.gate.x=0.05", "numerics.reorder_every=0"});
  IsphSolver<2, WendlandC2<2>, TestSpace> b(viscous_gate);
  CHECK(stage_names(b) == std::vector<std::string>{"gate", "neighbors", "density_and_roles",
                                                   "predictor_viscous", "pressure_poisson",
                                                   "corrector", "move"});
}

TEST_CASE("the multigrid preconditioners give Jacobi's pressure, walled and periodic", "[isph]") {
  // a dam break's first steps (the water moves), tight CG stop, pressure compared
  // after 5 steps; x periodic exercises the aggregates' wrap
  for (const char* multigrid : {"multigrid", "additive_multigrid"}) {
    for (const char* periodic : {"none", "x"}) {
      std::vector<std::string> set = {"numerics.cg_tolerance=1e-12", "numerics.cg_density_tolerance=0",
                                      "geometry.tank.periodic=" + std::string(periodic),
                                      "geometry.fluid=[{lo: [0, 0], hi: [0.05, 0.1]}]", "metrics.kind=none"};
      const Scene jacobi_scene = parse_scene(tank_2d, set);
      set.push_back("numerics.cg_preconditioner=" + std::string(multigrid));
      const Scene mg_scene = parse_scene(tank_2d, set);
      IsphSolver<2, WendlandC2<2>, TestSpace> jacobi(jacobi_scene), mg(mg_scene);
      int jacobi_iterations = 0, mg_iterations = 0;
      for (int step = 0; step < 5; ++step) {
        jacobi_iterations += jacobi.step().cg_iterations;
        mg_iterations += mg.step().cg_iterations;
      }
      auto pj = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), jacobi.pressure());
      auto pm = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), mg.pressure());
      double diff = 0, scale = 0;
      for (int i = 0; i < jacobi.size(); ++i) {
        diff = std::max(diff, std::abs(pj(i, 0) - pm(i, 0)));
        scale = std::max(scale, std::abs(pj(i, 0)));
      }
      WARN("periodic " << periodic << ": CG iterations over 5 steps, Jacobi " << jacobi_iterations
                       << ", " << multigrid << " " << mg_iterations << "; pressure difference " << diff / scale);
      CHECK(scale > 100);
      CHECK(diff / scale < 1e-8);
      // the additive form trades iterations for matrix applications: on these small tanks
      // it is not always below Jacobi's count (x periodic: 208 against 197)
      if (std::string(multigrid) == "multigrid") CHECK(mg_iterations < jacobi_iterations);
    }
  }
}

TEST_CASE("a damped start scales the corrected velocity by exp(-dt / settle_time)", "[isph]") {
  const Scene plain = parse_scene(tank_2d);
  const Scene damped = parse_scene(tank_2d, {"numerics.settle_until=0.1", "numerics.settle_time=0.004"});
  IsphSolver<2, WendlandC2<2>, TestSpace> a(plain), b(damped);
  const auto names = stage_names(b);
  CHECK(std::find(names.begin(), names.end(), "settle_damping") - std::find(names.begin(), names.end(), "corrector") == 1);
  const double dt = a.info().dt;
  REQUIRE(dt == b.info().dt);
  a.step();
  b.step();
  auto va = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.particles().v);
  auto vb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), b.particles().v);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a.particles().kind);
  const double factor = std::exp(-dt / 0.004);
  double worst = 0, largest = 0;
  for (int i = 0; i < a.size(); ++i)
    for (int k = 0; k < 2; ++k) {
      const double expect = kind(i) == Kind::fluid ? factor * va(i, k) : va(i, k);
      worst = std::max(worst, std::abs(vb(i, k) - expect));
      largest = std::max(largest, std::abs(va(i, k)));
    }
  REQUIRE(largest > 0);
  CHECK(worst <= 1e-14 * largest);
}

namespace {
struct TankResult {
  HydrostaticErrors errors;
  double worst_density_error = 0, final_density_error = 0;
  double max_transport_shift_over_h = 0;
  int pressure_columns = 0;
  bool kept_all = false;
};

TankResult run_tank(const std::vector<std::string>& overrides, int steps) {
  const Scene s = parse_scene(tank_2d, overrides);
  IsphSolver<2, WendlandC2<2>, TestSpace> solver(s);
  const int fluid = solver.count(Kind::fluid);
  TankResult r;
  DensityError<TestSpace> density_error;
  for (int step = 0; step < steps; ++step) {
    solver.step();  // throws if a particle leaves the domain or CG fails
    const auto e = density_error.paper_rule<2>(solver.neighbors(), solver.particles().kind,
                                               solver.density(), solver.pressure(), solver.truncation(),
                                               solver.reference_density(), solver.size());
    r.worst_density_error = std::max(r.worst_density_error, double(e.max));
    r.final_density_error = e.max;
    r.max_transport_shift_over_h =
        std::max(r.max_transport_shift_over_h, solver.info().transport_shift / solver.kernel().h);
  }
  r.pressure_columns = static_cast<int>(solver.pressure().extent(1));
  r.errors = hydrostatic_errors<2>(solver, s);
  r.kept_all = solver.count(Kind::fluid) == fluid;
  WARN("after " << steps << " steps: P error max " << r.errors.max_over_rho_g_H << " rms "
                << r.errors.rms_over_rho_g_H << " of rho g H; max density error "
                << r.worst_density_error << " (at the end " << r.final_density_error
                << "); max speed " << solver.info().max_speed << " m/s");
  return r;
}
}  // namespace

TEST_CASE("hydrostatic tank, 2D, 400 steps", "[isph]") {
  const auto r = run_tank({}, 400);
  CHECK(r.kept_all);
  CHECK(r.errors.checked > 300);
  CHECK(r.errors.max_over_rho_g_H < 0.01);
  CHECK(r.worst_density_error < 0.01);
}

// The density-invariance term must do what it is for: from a disordered start (0.1 dx
// jitter) gamma = 1 brings the density error below half of what gamma = 0 leaves, and
// keeps the pressure hydrostatic. (The test before ran a regular lattice, where gamma = 0
// stays within the bound too: it passed with the term deleted.)
TEST_CASE("hydrostatic tank, 2D, jittered: gamma = 1 halves the density error of gamma = 0", "[isph]") {
  const auto r0 = run_tank({"numerics.gamma=0", "geometry.jitter=0.1"}, 400);
  const auto r1 = run_tank({"numerics.gamma=1", "geometry.jitter=0.1"}, 400);
  CHECK(r0.kept_all);
  CHECK(r1.kept_all);
  CHECK(r1.final_density_error < 0.5 * r0.final_density_error);
  // regression bounds (measured 2026-12-01: max 0.033, rms 0.010 of rho g H; gamma = 0:
  // 0.012, 0.004): the disordered start still moves the pressure at gamma = 1 after 400
  // steps, beyond the 1 % of the regular tank
  CHECK(r1.errors.max_over_rho_g_H < 0.04);
  CHECK(r1.errors.rms_over_rho_g_H < 0.012);
}

// The selective dual-velocity step (method.md §1): with alpha = 0 the physical velocity
// is divergence-free only, and the density term acts through the transport velocity
// (beta = 0.5) alone; it must still restore the density of a disordered start, as
// gamma = 1 does above, while moving particles only a little off the physical path
// (measured 2026-12-01: 0.018 h at most on this tank at dx = 2.5 mm).
TEST_CASE("hydrostatic tank, 2D, jittered: alpha = 0, beta = 0.5 restores the density", "[isph]") {
  const auto r0 = run_tank({"numerics.gamma=0", "geometry.jitter=0.1"}, 400);
  const auto dual = run_tank({"numerics.alpha=0", "numerics.beta=0.5", "geometry.jitter=0.1"}, 400);
  CHECK(r0.pressure_columns == 1);
  CHECK(dual.pressure_columns == 2);
  CHECK(dual.kept_all);
  CHECK(dual.final_density_error < 0.5 * r0.final_density_error);
  CHECK(dual.max_transport_shift_over_h > 0);
  CHECK(dual.max_transport_shift_over_h < 0.2);
  CHECK(dual.errors.max_over_rho_g_H < 0.04);  // regression bound, as for gamma = 1
}

// Coarse dam break (a/dx = 20) to T = 3.5, the front against every Martin & Moyce point
// in T in [0.5, 3.5] (five) after the stated time-origin shift: 0.175 in T, the one the
// Lethe examples apply (docs/validation.md). Limit: 10 % at every point (issue 3's
// limit on the RMS; measured 2026-12-01: at most 3.5 %). Water in the walls: a
// regression bound (measured 0 dx; 0.017 dx before the wall condition).
TEST_CASE("dam break 2D, a/dx = 20, front against Martin & Moyce", "[isph]") {
  const Scene s = parse_scene(R"(
dimension: 2
end_time: 0.17
geometry:
  spacing: 0.0025
  tank: {lo: [0, 0], hi: [0.3, 0.12]}
  fluid: [{lo: [0, 0], hi: [0.05, 0.1]}]
metrics: {kind: dam_break, column_width: 0.05}
)");
  IsphSolver<2, WendlandC2<2>, TestSpace> solver(s);
  const auto walls = tank_walls<2>(s);
  const double a = s.column_width, scale = std::sqrt(2 * 9.81 / a), shift = 0.175;
  FrontData sim;
  double penetration = 0;
  const ConnectedFront<TestSpace> front(s.tank.lo[0], s.tank.hi[0], s.spacing, 3);  // as the run's
  while (solver.info().t < s.end_time) {
    solver.step();
    penetration = std::max(penetration, deepest_in_walls(solver, walls));
    sim.T.push_back(solver.info().t * scale);
    const auto& p = solver.particles();
    sim.Z.push_back(front(FluidFrontCoordinate<decltype(p.x), decltype(p.kind)>{p.x, p.kind},
                          solver.size()) / a);
  }
  const auto dev = front_deviations(sim, martin_moyce(), 0.5, 3.5, shift);
  REQUIRE(dev.size() == 5);
  for (const double d : dev) {
    WARN("front deviation after the shift: " << d);
    CHECK(std::abs(d) < 0.10);
  }
  WARN("deepest fluid particle past the tank faces: " << penetration / s.spacing << " dx");
  CHECK(penetration < 0.05 * s.spacing);
}

// The front driven into the far wall (a/dx = 20, the tank 0.2 m long, to T = 7): the
// wall condition must stop the water at the wall. With the hydrostatic continuation
// alone a particle went through the wall and left the domain at t = 0.317 s
// (docs/stability.md, dam_break_2d_impact), which throws here. Measured now: 0.033 dx.
TEST_CASE("dam break 2D driven into the far wall: the wall holds", "[isph]") {
  const Scene s = parse_scene(R"(
dimension: 2
end_time: 0.35
geometry:
  spacing: 0.0025
  wall_layers: 6
  tank: {lo: [0, 0], hi: [0.2, 0.4]}
  fluid: [{lo: [0, 0], hi: [0.05, 0.1]}]
)");
  IsphSolver<2, WendlandC2<2>, TestSpace> solver(s);
  const auto walls = tank_walls<2>(s);
  double penetration = 0;
  while (solver.info().t < s.end_time) {
    solver.step();
    penetration = std::max(penetration, deepest_in_walls(solver, walls));
  }
  WARN("deepest fluid particle inside the walls: " << penetration / s.spacing << " dx");
  CHECK(penetration < 0.25 * s.spacing);
}
