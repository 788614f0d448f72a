// DEM of the glass beads against known answers (method.md §3, §6): restitution of the
// linear spring-dashpot, momentum conservation, sliding and rolling with Coulomb
// friction, energy decay while a bed settles, contact history across reordering.
#include "tests/dem_scenes.hpp"
#include "tests/test_space.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using namespace dvisph;
using namespace dvisph::dem;
using namespace dvisph::testing;
using Mem = typename TestSpace::memory_space;

namespace {

constexpr Real g0 = 9.81;

template <int D>
Vec<D> axis(int k, Real s = 1) {
  Vec<D> v = Vec<D>::zero();
  v[k] = s;
  return v;
}
template <int D>
Vec<D> filled(Real s) {
  Vec<D> v;
  for (int k = 0; k < D; ++k) v[k] = s;
  return v;
}

template <class View>
void set_row(const View& field, int i, const std::vector<Real>& values) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), field);
  for (std::size_t c = 0; c < values.size(); ++c) h(i, c) = values[c];
  Kokkos::deep_copy(field, h);
}

// Rebound of the paper's bead at 1 m/s without gravity: off a wall (returns the normal
// speed after over before) or off an equal bead (relative speeds). The gap before
// contact is (3 + phase) steps, so the contact starts at that fraction of a step.
// across_seam: the two beads meet across the periodic face x = +-0.02 of the box.
template <int D>
Real rebound(Real e, bool wall, Real safety, Real phase, bool non_attractive = false,
             bool across_seam = false) {
  const Real r = 0.5 * bead_d;
  LinearSpringDashpot<D> law(bead_kn, e, 0.2);
  law.non_attractive = non_attractive;
  DemOptions<D> opt;
  opt.safety = safety;
  const Real m = bead_rho * 4.0 / 3.0 * math::pi * r * r * r;
  const Real dt = safety * law.contact_time(0.5 * m);  // as the solver picks it
  const Real gap = (3 + phase) * dt * 1.0;
  std::vector<Vec<D>> x;
  std::vector<PlaneWall<D>> walls;
  if (wall) {
    x = {axis<D>(D - 1, r + gap)};
    walls = {PlaneWall<D>(Vec<D>::zero(), axis<D>(D - 1))};
  } else {
    x = {axis<D>(0, -r - 0.5 * gap), axis<D>(0, r + 0.5 * gap)};
  }
  if (across_seam) {
    x[0][0] += 0.02;
    x[1][0] -= 0.02;
    opt.periodic_axes = 1;
  }
  Spheres<D, TestSpace> s(x, r, bead_rho);
  const int normal = wall ? D - 1 : 0;
  auto hv = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.v);
  if (wall) {
    hv(0, normal) = -1;
  } else {
    hv(0, 0) = 0.5;
    hv(1, 0) = -0.5;
  }
  Kokkos::deep_copy(s.v, hv);
  DemSolver<D, TestSpace> dem(s, walls, law, filled<D>(-0.02), filled<D>(0.02), Vec<D>::zero(),
                              opt);
  REQUIRE(dem.time_step() == Approx(dt).epsilon(1e-14));
  const int steps = static_cast<int>((gap + 2 * law.contact_time(wall ? m : 0.5 * m)) / dt) + 5;
  bool touched = false;
  for (int n = 0; n < steps; ++n) {
    dem.step(dt);
    touched = touched || dem.contacts_per_bead() > 0;
  }
  REQUIRE(touched);
  REQUIRE(dem.contacts_per_bead() == 0);
  const auto v = by_id(s.v, s.id);
  return wall ? v[0][normal] : v[1][0] - v[0][0];
}

// A bead launched at v0 along a floor with mu = 0.2 (e = 0.9, gravity): returns its speed
// and the distance it travelled after `time`.
template <int D>
std::pair<Real, Real> slide(Real v0, Real time, bool rotation) {
  const Real r = 0.5 * bead_d;
  const Real m = bead_rho * 4.0 / 3.0 * math::pi * r * r * r;
  const LinearSpringDashpot<D> law(bead_kn, 0.9, 0.2);
  DemOptions<D> opt;
  opt.rotation = rotation;
  // resting on the floor: overlap m g / k_n
  Spheres<D, TestSpace> s({axis<D>(D - 1, r - m * g0 / bead_kn)}, r, bead_rho);
  set_row(s.v, 0, [&] {
    std::vector<Real> v(D, 0);
    v[0] = v0;
    return v;
  }());
  Vec<D> lo = filled<D>(-0.01), hi = filled<D>(0.01);
  hi[0] = 0.2;
  DemSolver<D, TestSpace> dem(s, {PlaneWall<D>(Vec<D>::zero(), axis<D>(D - 1))}, law, lo, hi,
                              axis<D>(D - 1, -g0), opt);
  const int steps = static_cast<int>(time / dem.time_step());
  for (int n = 0; n < steps; ++n) dem.step(dem.time_step());
  const auto x = by_id(s.x, s.id), v = by_id(s.v, s.id);
  return {v[0][0], x[0][0]};
}

}  // namespace

TEST_CASE("contact law constants follow from e, and the contact time from m*", "[dem]") {
  const LinearSpringDashpot<3> law(bead_kn, 0.9, 0.2);
  const Real m = bead_rho * math::pi / 6 * bead_d * bead_d * bead_d;
  CHECK(m == Approx(2.577e-5).epsilon(1e-3));  // method.md §3
  CHECK(law.zeta == Approx(0.0335).epsilon(1e-3));
  CHECK(law.contact_time(0.5 * m) == Approx(3.57e-4).epsilon(2e-3));
  CHECK(law.contact_time(m) == Approx(5.05e-4).epsilon(2e-3));
  CHECK(law.k_t == Approx(2.0 / 7.0 * bead_kn));
}

TEST_CASE("beads rebound with the restitution coefficient e", "[dem]") {
  // error vs step: the contact's start and end are placed inside the step, so e
  // converges at second order in dt/t_c
  for (const Real e : {0.5, 0.7, 0.9, 0.95})
    for (const bool wall : {true, false}) {
      Real worst = 0, worst_default = 0;
      for (const Real phase : {0.13, 0.5, 0.87}) {
        worst = std::max(worst, std::abs(rebound<3>(e, wall, 1.0 / 100, phase) / e - 1));
        worst_default =
            std::max(worst_default, std::abs(rebound<3>(e, wall, 1.0 / 25, phase) / e - 1));
      }
      const Real e2 = rebound<2>(e, wall, 1.0 / 100, 0.5);
      WARN("e = " << e << (wall ? " wall" : " pair") << ": max |e_num/e - 1| = " << worst
                  << " at dt = t_c/100, " << worst_default << " at t_c/25; 2D " << e2 / e - 1);
      CHECK(worst < 1e-3);
      CHECK(std::abs(e2 / e - 1) < 1e-3);
      // the paper's e = 0.9 and above meet it at the default step too
      if (e >= 0.9) CHECK(worst_default < 1e-3);
    }
}

TEST_CASE("beads meeting across a periodic face rebound as anywhere else", "[dem]") {
  for (const Real e : {0.9, 0.5}) {
    const Real inside = rebound<3>(e, false, 0.04, 0.3);
    CHECK(rebound<3>(e, false, 0.04, 0.3, false, true) == Approx(inside).epsilon(1e-9));
    CHECK(rebound<2>(e, false, 0.04, 0.3, false, true) == Approx(rebound<2>(e, false, 0.04, 0.3)).epsilon(1e-9));
  }
}

TEST_CASE("a non-attractive normal force makes beads rebound faster than e", "[dem]") {
  for (const Real e : {0.5, 0.7, 0.9, 0.95}) {
    const Real clamped = rebound<3>(e, true, 1.0 / 100, 0.5, true);
    WARN("e = " << e << ": clamped F_n >= 0 rebounds at " << clamped << " (" << clamped / e - 1
                << " relative)");
    CHECK(clamped / e - 1 > 1e-4);  // beyond the discretization error at this step
  }
}

TEST_CASE("a two-bead collision conserves linear momentum", "[dem]") {
  const auto s = two_bead_collision<TestSpace>();
  // rows: m, x(3), v(3), omega(3); initial velocities (0.8, 0, 0) and (-0.3, 0, 0.05)
  const Real p0[3] = {s[0][0] * 0.8 - s[1][0] * 0.3, 0, s[1][0] * 0.05};
  Real err2 = 0, p02 = 0;
  for (int k = 0; k < 3; ++k) {
    const Real p = s[0][0] * s[0][4 + k] + s[1][0] * s[1][4 + k];
    err2 += (p - p0[k]) * (p - p0[k]);
    p02 += p0[k] * p0[k];
  }
  WARN("two-bead collision: |p - p0| / |p0| = " << std::sqrt(err2 / p02));
  CHECK(std::sqrt(err2 / p02) <= 1e-12);
  CHECK(s[0][4] < 0.5);                                 // they did collide
  CHECK(std::abs(s[0][7]) + std::abs(s[0][8]) > 1e-3);  // and friction spun them
}

TEST_CASE("a bead sliding on a floor ends rolling at 5/7 v0, or stops at v0^2/(2 mu g)", "[dem]") {
  const Real v0 = 0.5, mu = 0.2;
  const Real t_roll = 2 * v0 / (7 * mu * g0), t_stop = v0 / (mu * g0);
  const auto rolling3 = slide<3>(v0, 2 * t_roll, true);
  const auto rolling2 = slide<2>(v0, 2 * t_roll, true);
  const auto sliding3 = slide<3>(v0, 1.3 * t_stop, false);
  const Real stop = v0 * v0 / (2 * mu * g0);
  WARN("rolling speed / (5/7 v0) - 1: 3D "
       << rolling3.first / (5.0 / 7 * v0) - 1 << ", 2D " << rolling2.first / (5.0 / 7 * v0) - 1
       << "; stop distance / (v0^2/(2 mu g)) - 1: " << sliding3.second / stop - 1);
  CHECK(rolling3.first == Approx(5.0 / 7 * v0).epsilon(1e-4));
  CHECK(rolling2.first == Approx(5.0 / 7 * v0).epsilon(1e-4));
  CHECK(std::abs(sliding3.first) < 1e-4 * v0);
  CHECK(sliding3.second == Approx(stop).epsilon(1e-4));
}

TEST_CASE("total energy never increases while a bed of beads settles", "[dem]") {
  const Real d = bead_d;
  const Vec<3> lo = Vec<3>::zero(), hi = vec<3>(8 * d, 8 * d, 30 * d);
  // 6 x 6 x 8 jittered beads, 1.15 d apart, falling with random velocities
  std::vector<Vec<3>> x;
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int c = 0; c < 8 * 36; ++c)
    x.push_back(vec<3>((0.9 + 1.15 * (c % 6) + 0.05 * u(rng)) * d,
                       (0.9 + 1.15 * (c / 6 % 6) + 0.05 * u(rng)) * d,
                       (0.6 + 1.15 * (c / 36)) * d));
  Spheres<3, TestSpace> s(x, 0.5 * d, bead_rho);
  {
    auto h = Kokkos::create_mirror_view(s.v);
    for (std::size_t i = 0; i < x.size(); ++i)
      for (int k = 0; k < 3; ++k) h(i, k) = 0.1 * u(rng);
    Kokkos::deep_copy(s.v, h);
  }
  DemSolver<3, TestSpace> dem(s, box_walls<3>(lo, hi), LinearSpringDashpot<3>(bead_kn, 0.9, 0.2),
                              lo, hi, vec<3>(0, 0, -g0));
  const Real e0 = dem.energy().total();
  Real previous = e0, max_increase = 0;
  const int steps = static_cast<int>(0.25 / dem.time_step());
  for (int n = 0; n < steps; ++n) {
    dem.step(dem.time_step());
    const Real now = dem.energy().total();
    max_increase = std::max(max_increase, now - previous);
    previous = now;
  }
  const Energy end = dem.energy();
  WARN("settle of " << x.size() << " beads over " << steps << " steps: E0 = " << e0
                    << " J, E_end = " << end.total() << " J (kinetic " << end.kinetic
                    << "), max step increase = " << max_increase << " J = " << max_increase / e0
                    << " E0, contacts per bead " << dem.contacts_per_bead());
  CHECK(max_increase <= 1e-13 * e0);  // round-off
  CHECK(end.kinetic < 1e-3 * e0);     // it did settle
}

TEST_CASE("contact history survives reordering mid-contact", "[dem]") {
  // a pyramid of three beads, a bead at rest and a sliding bead, all on a floor
  const Real r = 0.5 * bead_d, m = bead_rho * 4.0 / 3.0 * math::pi * r * r * r;
  const Real z = r - m * g0 / bead_kn;
  const std::vector<Vec<3>> x = {vec<3>(0.02, 0.01, z), vec<3>(0.02 + 2 * r, 0.01, z),
                                 vec<3>(0.02 + r, 0.01, z + std::sqrt(3.0) * r),
                                 vec<3>(0.01, 0.002, z), vec<3>(0.005, 0.005, z)};
  const Vec<3> lo = Vec<3>::zero(), hi = vec<3>(0.1, 0.02, 0.02);
  // through_table: every step the list is rebuilt through the id-keyed table (an identity
  // permute), where the reference carries it from list to list at its own builds
  enum class Reorder { none, with_history, naive, through_table };
  const auto run = [&](Reorder how) {
    Spheres<3, TestSpace> s(x, r, bead_rho);
    set_row(s.v, 4, {0.3, 0.1, 0});
    DemSolver<3, TestSpace> dem(s, {PlaneWall<3>(lo, vec<3>(0, 0, 1))},
                                LinearSpringDashpot<3>(bead_kn, 0.9, 0.2), lo, hi,
                                vec<3>(0, 0, -g0));
    Kokkos::View<int*, Mem> reverse("reverse", s.n), identity("identity", s.n);
    const int order[] = {4, 3, 2, 1, 0}, same[] = {0, 1, 2, 3, 4};
    Kokkos::deep_copy(reverse, Kokkos::View<const int*, Kokkos::HostSpace>(order, 5));
    Kokkos::deep_copy(identity, Kokkos::View<const int*, Kokkos::HostSpace>(same, 5));
    for (int n = 0; n < 1500; ++n) {
      if (how == Reorder::through_table) dem.permute(identity);
      if ((n == 500 || n == 900) && how == Reorder::with_history) {
        // the springs' energy (normal and tangential) is the same in the new order
        const Real before = dem.energy().spring;
        if (n == 500) dem.permute(reverse);
        if (n == 900) dem.reorder();
        CHECK(dem.energy().spring == Approx(before).epsilon(1e-12));
      }
      if (n == 500 && how == Reorder::naive)  // the beads move, their history rows do not
        s.for_each_field([&](const char*, auto& field) {
          using V = std::decay_t<decltype(field)>;
          const V tmp("tmp", field.layout());
          gather_rows<TestSpace>(tmp, field, reverse);
          Kokkos::deep_copy(field, tmp);
        });
      dem.step(dem.time_step());
    }
    REQUIRE(dem.contacts_per_bead() > 1);
    if (how == Reorder::none) REQUIRE(dem.list_builds() > 3);  // lists rebuilt mid-contact
    auto state = by_id(s.x, s.id);
    for (const auto& rows : {by_id(s.v, s.id), by_id(s.omega, s.id)})
      for (std::size_t i = 0; i < rows.size(); ++i)
        state[i].insert(state[i].end(), rows[i].begin(), rows[i].end());
    return state;
  };
  const auto difference = [](const auto& a, const auto& b) {
    Real worst = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
      for (std::size_t c = 0; c < a[i].size(); ++c)
        worst = std::max(worst, std::abs(a[i][c] - b[i][c]) / (std::abs(a[i][c]) + 1e-3));
    return worst;
  };
  const auto reference = run(Reorder::none);
  const Real kept = difference(run(Reorder::with_history), reference);
  const Real naive = difference(run(Reorder::naive), reference);
  const Real table = difference(run(Reorder::through_table), reference);
  WARN("reordered with history: " << kept << "; reordered without moving the history: " << naive
                                   << "; lists through the table: " << table);
  CHECK(kept < 1e-12);
  CHECK(table < 1e-12);
  CHECK(naive > 1e-6);  // the test can see a lost history
}

TEST_CASE("an external force is held over a fluid step", "[dem]") {
  const Real r = 0.5 * bead_d, F = 1e-4;
  Spheres<3, TestSpace> s({vec<3>(0, 0, 0)}, r, bead_rho);
  set_row(s.f_ext, 0, {F, 0, -0.5 * F});
  DemSolver<3, TestSpace> dem(s, {}, LinearSpringDashpot<3>(bead_kn, 0.9, 0.2), filled<3>(-0.01),
                              filled<3>(0.01), Vec<3>::zero());
  const Real T = 7.3 * dem.time_step();  // 8 sub-steps
  dem.advance(T);
  const Real a = F / by_id(s.mass, s.id)[0][0];
  const auto v = by_id(s.v, s.id)[0], x = by_id(s.x, s.id)[0];
  CHECK(dem.time() == Approx(T).epsilon(1e-14));
  CHECK(v[0] == Approx(a * T).epsilon(1e-12));  // velocity Verlet is exact here
  CHECK(v[2] == Approx(-0.5 * a * T).epsilon(1e-12));
  CHECK(x[0] == Approx(0.5 * a * T * T).epsilon(1e-12));
}

TEST_CASE("a gate stops beads until it is removed", "[dem]") {
  const Real r = 0.5 * bead_d;
  const auto run = [&](Real open_at) {
    Spheres<2, TestSpace> s({vec<2>(-2 * r, 0)}, r, bead_rho);
    set_row(s.v, 0, {1, 0});
    DemSolver<2, TestSpace> dem(s, {PlaneWall<2>(Vec<2>::zero(), vec<2>(-1, 0), open_at)},
                                LinearSpringDashpot<2>(bead_kn, 0.9, 0.2), filled<2>(-0.02),
                                filled<2>(0.02), Vec<2>::zero());
    dem.advance(4e-3);
    return by_id(s.v, s.id)[0][0];
  };
  CHECK(run(1e-3) == Approx(1));                  // removed before the bead arrives
  CHECK(run(1.0) == Approx(-0.9).epsilon(0.01));  // stays: the bead bounces
}

TEST_CASE("a gate removed mid-contact leaves no contact behind", "[dem]") {
  const Real r = 0.5 * bead_d;
  Spheres<2, TestSpace> s({vec<2>(-r + 1e-6, 0)}, r, bead_rho);  // pressed on the gate
  set_row(s.v, 0, {0.1, 0.05});
  DemSolver<2, TestSpace> dem(s, {PlaneWall<2>(Vec<2>::zero(), vec<2>(-1, 0), 1e-4)},
                              LinearSpringDashpot<2>(bead_kn, 0.9, 0.2), filled<2>(-0.02),
                              filled<2>(0.02), Vec<2>::zero());
  dem.step(dem.time_step());
  REQUIRE(dem.contacts_per_bead() == 1);
  dem.advance(1e-3);
  CHECK(dem.contacts_per_bead() == 0);
  CHECK(dem.energy().spring == 0);
}

TEST_CASE("a full contact history is reported, not dropped", "[dem]") {
  const Real r = 0.5 * bead_d, c = 1.99 * r;
  Spheres<2, TestSpace> s({vec<2>(0, 0), vec<2>(c, 0), vec<2>(-c, 0), vec<2>(0, c)}, r, bead_rho);
  DemOptions<2> opt;
  opt.history_capacity = 2;
  DemSolver<2, TestSpace> dem(s, {}, LinearSpringDashpot<2>(bead_kn, 0.9, 0.2), filled<2>(-0.01),
                              filled<2>(0.01), Vec<2>::zero(), opt);
  CHECK_THROWS_AS(dem.step(dem.time_step()), std::runtime_error);
}
