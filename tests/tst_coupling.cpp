// Water and beads: the drag closures against their published forms, and the exchange
// of momentum between the water and the beads in a step.
#include "kernels/wendland_c2.hpp"
#include "solvers/isph/isph_solver.hpp"
#include "src/scene.hpp"
#include "src/scene_beads.hpp"
#include "test_space.hpp"
#include "tests/coupled_scenes.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace dvisph;
using Mem = TestSpace::memory_space;

namespace {

constexpr double rho = 1000, nu = 1e-6, d = 0.0027;

}  // namespace

TEST_CASE("coupling: Ergun's pressure gradient through a fixed bed (method.md §2)", "[coupling]") {
  // steady flow through a fixed bed: eps grad P balances the drag K u, u = q / eps
  const DragLaw law("ergun_wen_yu", rho, nu, d, 0.8);
  const double eps = 0.4;
  const double q[3] = {1e-3, 1e-2, 5e-2}, expected[3] = {122, 1765, 20978};  // Pa/m
  for (int k = 0; k < 3; ++k) {
    const double u = q[k] / eps;
    const double exact = 150 * rho * nu * std::pow(1 - eps, 2) * q[k] / (std::pow(eps, 3) * d * d) +
                         1.75 * rho * (1 - eps) * q[k] * q[k] / (std::pow(eps, 3) * d);
    CHECK(law(eps, u) * u / eps == Approx(exact).epsilon(1e-12));
    CHECK(law(eps, u) * u / eps == Approx(expected[k]).epsilon(2e-3));  // method.md's rounding
  }
}

TEST_CASE("coupling: one bead in clear water gets its single-sphere drag", "[coupling]") {
  // K u V_s / (1 - eps) = C_d pi d^2 / 8 rho u^2 eps^-exponent, Re = eps rho u d / mu
  const double eps = 0.999, u = 0.3, vs = math::pi / 6 * d * d * d;
  const double re = eps * u * d / nu;
  const DragLaw wen_yu("ergun_wen_yu", rho, nu, d, 0.8), di_felice("di_felice", rho, nu, d, 0.8);
  const double cd_sn = 24 / re * (1 + 0.15 * std::pow(re, 0.687));
  CHECK(wen_yu(eps, u) * u * vs / (1 - eps) ==
        Approx(cd_sn * math::pi * d * d / 8 * rho * u * u * std::pow(eps, -1.65)).epsilon(1e-12));
  const double cd_df = std::pow(0.63 + 4.8 / std::sqrt(re), 2);
  const double chi = 3.7 - 0.65 * std::exp(-0.5 * std::pow(1.5 - std::log10(re), 2));
  CHECK(di_felice(eps, u) * u * vs / (1 - eps) ==
        Approx(cd_df * math::pi * d * d / 8 * rho * eps * eps * u * u * std::pow(eps, -chi)).epsilon(1e-12));
  // the choice is real: Di Felice drags a 2.7 mm bead at 0.3 m/s harder
  CHECK(di_felice(eps, u) > 1.1 * wen_yu(eps, u));
}

namespace {

struct Momentum {
  double p[3] = {0, 0, 0};
  double scale = 0;  // sum of |m dv| over particles and axes
};

}  // namespace

TEST_CASE("coupling: water and beads exchange momentum exactly", "[coupling]") {
  using Solver = IsphSolver<3, WendlandC2<3>, TestSpace, PorousMedium<3, TestSpace>>;
  const Scene s = parse_scene(testing::coupled_blob);
  auto beads = scene_dem<3, TestSpace>(s);
  Solver solver(s, &beads);
  for (int step = 0; step < 5; ++step) {
    const int n = solver.size();
    const auto& p = solver.particles();
    const auto v0 = testing::snapshot_of(p.v);
    const auto w0 = testing::snapshot_of(beads.spheres().v);
    const auto id0 = testing::snapshot_of(beads.spheres().id);
    const double dt = solver.info().dt;
    solver.step();
    const auto v1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.v);
    const auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.m);
    const auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.kind);
    const auto eps = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver.medium().eps);
    const auto icr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver.medium().inv_cr);
    const auto w1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), beads.spheres().v);
    const auto id1 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), beads.spheres().id);
    const auto mb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), beads.spheres().mass);
    // the momentum of a fluid particle in its step is C_r m u_f = C_r m v / eps
    Momentum change;
    double mass = 0, ball_in_bed = 1;
    for (int i = 0; i < n; ++i) {
      if (kind(i) != Kind::fluid) continue;
      mass += m(i);
      ball_in_bed = std::min(ball_in_bed, eps(i));
      for (int k = 0; k < 3; ++k) {
        const double dp = m(i) / (icr(i) * eps(i)) * (v1(i, k) - v0(i, k));
        change.p[k] += dp;
        change.scale += std::abs(dp);
      }
    }
    std::vector<double> before(3 * beads.spheres().n);
    for (int b = 0; b < beads.spheres().n; ++b)
      for (int k = 0; k < 3; ++k) before[3 * id0(b) + k] = w0(b, k);
    for (int b = 0; b < beads.spheres().n; ++b) {
      mass += mb(b);
      for (int k = 0; k < 3; ++k) {
        const double dp = mb(b) * (w1(b, k) - before[3 * id1(b) + k]);
        change.p[k] += dp;
        change.scale += std::abs(dp);
      }
    }
    REQUIRE(ball_in_bed < 0.95);  // the beads are in the water
    // only gravity changes the total: m g dt
    for (int k = 0; k < 3; ++k) {
      INFO("step " << step << " axis " << k << ": change " << change.p[k] << ", gravity "
                   << mass * s.gravity[k] * dt << ", scale " << change.scale);
      CHECK(std::abs(change.p[k] - mass * s.gravity[k] * dt) < 1e-10 * change.scale);
    }
  }
}

TEST_CASE("coupling: water driven through a periodic fixed bed flows at Ergun's velocity", "[coupling]") {
  // scenes/ergun_bed_2d.yaml at 5 cm/s for 0.1 s: the water crosses the periodic faces
  // (u_f = q / eps = 12.5 cm/s, 0.55 box lengths), and none is lost
  using Solver = IsphSolver<2, WendlandC2<2>, TestSpace, PorousMedium<2, TestSpace>>;
  const double L = 0.02270021436, drive = 20.978;  // m, m/s^2
  const Scene s = parse_scene(R"(
name: ergun_test
dimension: 2
end_time: 0.1
material: {density: 1000, kinematic_viscosity: 1.0e-6, gravity: [20.978, 0]}
geometry:
  spacing: 0.00126112302
  tank: {lo: [0, 0], hi: [0.02270021436, 0.02270021436], open_top: false, periodic: xy}
  fluid: [{lo: [0, 0], hi: [0.02270021436, 0.02270021436]}]
solids:
  diameter: 0.0027
  fixed: true
  lattice: [{lo: [0, 0], hi: [0.02270021436, 0.02270021436]}]
  lattice_spacing: 0.9341652
coupling: {smoothing_length: 0.00378336906}
)");
  auto beads = scene_dem<2, TestSpace>(s);
  Solver solver(s, &beads);
  const int n0 = solver.size();
  while (solver.info().t < s.end_time) solver.step();
  REQUIRE(solver.size() == n0);
  const auto& p = solver.particles();
  const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.v);
  const auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.m);
  const auto eps = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver.medium().eps);
  double flux = 0, volume = 0, lowest = L, highest = 0;
  for (int i = 0; i < n0; ++i) {
    flux += m(i) / eps(i) * v(i, 0);
    volume += m(i) / eps(i);
    for (int k = 0; k < 2; ++k) lowest = std::min(lowest, x(i, k)), highest = std::max(highest, x(i, k));
  }
  CHECK(lowest >= 0);
  CHECK(highest < L);
  // Ergun's superficial velocity for the drive rho g at eps = 0.4: the root of
  // 150 mu (1 - eps)^2 q / (eps^3 d^2) + 1.75 rho (1 - eps) q^2 / (eps^3 d) = rho g
  const double e = 0.4, a = 1.75 * rho * (1 - e) / (e * e * e * d),
               b = 150 * rho * nu * (1 - e) * (1 - e) / (e * e * e * d * d);
  const double q = (-b + std::sqrt(b * b + 4 * a * rho * drive)) / (2 * a);
  CHECK(q == Approx(0.05).epsilon(1e-4));
  CHECK(flux / volume == Approx(q).epsilon(0.02));
}

// d eps/dt at a fluid particle (the PPE's porosity source, coupling.porosity_rate) is the
// rate at which the beads' motion changes its porosity: the fields' sum over
// V_s grad W . v_s against the central difference of eps with the beads moved by
// -+ v_s delta, at fixed fluid particles around three beads moving apart.
TEST_CASE("coupling: the porosity rate is the time derivative of the beads' porosity", "[coupling]") {
  using Space = TestSpace;
  const Real dx = 0.001, h_c = 0.0025;
  const std::vector<Vec<3>> centres = {{0.025, 0.025, 0.025}, {0.0255, 0.022, 0.0285}, {0.02, 0.028, 0.02}};
  const Real vel[3][3] = {{0.1, 0, -0.2}, {0, 0.05, 0}, {-0.1, 0.1, 0.3}};
  const int side = 16, n = side * side * side;
  Kokkos::View<Real* [3], Mem> x("x", n), v("v", n);
  Kokkos::View<Real*, Mem> m("m", n);
  Kokkos::View<Kind*, Mem> kind("kind", n);
  {
    auto hx = Kokkos::create_mirror_view(x);
    for (int i = 0; i < n; ++i) {
      const int c[3] = {i % side, (i / side) % side, i / (side * side)};
      for (int k = 0; k < 3; ++k) hx(i, k) = 0.015 + (c[k] + 0.5) * dx;
    }
    Kokkos::deep_copy(x, hx);
    Kokkos::deep_copy(m, rho * dx * dx * dx);
    Kokkos::deep_copy(kind, Kind::fluid);
  }
  const auto porosity = [&](Real delta, bool rate) {
    std::vector<Vec<3>> at = centres;
    for (std::size_t s = 0; s < at.size(); ++s)
      for (int k = 0; k < 3; ++k) at[s][k] += delta * vel[s][k];
    dem::Spheres<3, Space> beads(at, d / 2, 2500);
    auto hv = Kokkos::create_mirror_view(beads.v);
    for (int s = 0; s < beads.n; ++s)
      for (int k = 0; k < 3; ++k) hv(s, k) = vel[s][k];
    Kokkos::deep_copy(beads.v, hv);
    const CouplingOptions<3> o{h_c, 0.01, 1, rho, dx * dx * dx, Vec<3>{{0, 0, -9.81}}, rate};
    BeadCoupling<3, WendlandC2<3>, Space> coupling(o, DragLaw("ergun_wen_yu", rho, nu, d, 0.8),
                                                   VanGentVirtualMass{true}, Vec<3>{{0, 0, 0}},
                                                   Vec<3>{{0.05, 0.05, 0.05}}, 0);
    coupling.resize(n);
    const PorousMedium<3, Space> medium(n);
    coupling.fields(beads, x, v, m, kind, medium, 1e-4, n);
    return std::make_pair(testing::snapshot_of(medium.eps), testing::snapshot_of(medium.eps_rate));
  };
  const Real delta = 1e-6;  // s: the beads move 0.3 um at most
  const auto [eps, rate] = porosity(0, true);
  const auto ahead = porosity(delta, true).first, behind = porosity(-delta, true).first;
  Real largest = 0, worst = 0, lowest = 1;
  for (int i = 0; i < n; ++i) {
    const Real difference = (ahead(i) - behind(i)) / (2 * delta);
    largest = std::max(largest, std::abs(difference));
    worst = std::max(worst, std::abs(rate(i) - difference));
    lowest = std::min(lowest, eps(i));
  }
  INFO("largest |d eps/dt| " << largest << " 1/s, worst difference " << worst);
  REQUIRE(lowest < 0.9);     // the beads are among the particles
  REQUIRE(largest > 10);     // and move through them (beads at 0.05-0.33 m/s, h_c = 2.5 mm)
  CHECK(worst < 1e-7 * largest);  // measured 2.5e-8: the difference's own error
  const auto off = porosity(0, false).second;
  Real any = 0;
  for (int i = 0; i < n; ++i) any = std::max(any, std::abs(off(i)));
  CHECK(any == 0);  // coupling.porosity_rate: false
}
