#pragma once
// What series.csv, the snapshots and summary.json hold about the water and the beads
// together (src/simulation.hpp composes it with the outputs of each): the porosity, the
// water's force on the beads, and the coupled scenes' figures:
//   settling_bead    one bead's terminal velocity against that of the drag law at the
//                    porosity the bead sees (the mean of eps_i over the water around it,
//                    weighted by W_is as the drag it gets), and the slip it falls with
//   bed_hydrostatic  still water over and inside a bed: pressure against rho g (H - y),
//                    the fastest water and bead, and the water's force on the beads
//                    against their buoyancy sum rho_f V_s g (which makes the load on the
//                    floor their weight less buoyancy)
//   ergun_bed        a fixed bed in a box periodic along every axis, the water driven by
//                    a body force g (material.gravity) through it: at steady state the
//                    drag balances the drive, so rho_f |g| is the pressure gradient that
//                    would drive the same flow (K u_f = eps dP/dx in the closure's terms);
//                    it is compared with Ergun's formula at the bed's porosity
//                    1 - sum V_s / V_box and the measured superficial velocity
//                    q = sum V_i v_i / sum V_i (the formula written out here, not the
//                    drag law's code)
#include "solvers/isph/isph_solver.hpp"
#include "src/metrics.hpp"

#include <fmt/format.h>

#include <cmath>
#include <vector>

namespace dvisph {

template <int D, class Solver>
class CoupledOutput {
 public:
  using Space = typename Solver::execution_space;
  using Beads = dem::DemSolver<D, Space>;

  CoupledOutput(const Scene& s, const Solver& fluid, const Beads& beads)
      : s_(s), fluid_(fluid), beads_(beads), up_(up_axis(s)) {}

  void after_step() {}

  std::string series_header() const {
    return "porosity_min,beads_mean_velocity_up,fluid_force_on_beads_up,superficial_velocity_along_g";
  }
  std::string series_row() {
    const Real lowest = porosity_range().min_val;
    porosity_min_ = std::min(porosity_min_, static_cast<double>(lowest));
    const auto b = bead_sums();
    velocity_up_.push_back(b.velocity_up);
    t_.push_back(fluid_.info().t);
    const double q = -superficial_velocity_up();
    q_.push_back(q);
    return fmt::format("{:.6g},{:.9g},{:.9g},{:.9g}", lowest, b.velocity_up, b.force_up, q);
  }

  std::string metrics() const {
    std::string m = fmt::format("\"porosity_min_seen\": {:.4g}", porosity_min_);
    if (s_.metrics_kind == "settling_bead") m += settling();
    if (s_.metrics_kind == "bed_hydrostatic") m += bed_at_rest();
    if (s_.metrics_kind == "ergun_bed") m += ergun();
    return m;
  }

  // (The helpers below hold device lambdas: public, as nvcc requires.)
  static Vec<D> up_axis(const Scene& s) {
    Vec<D> up = Vec<D>::zero();
    Real g = 0;
    for (int k = 0; k < D; ++k) g += s.gravity[k] * s.gravity[k];
    for (int k = 0; k < D; ++k) up[k] = g > 0 ? -s.gravity[k] / std::sqrt(g) : (k == D - 1);
    return up;
  }

  // The range of eps_i over the fluid particles.
  Kokkos::MinMaxScalar<Real> porosity_range() const {
    const auto eps = fluid_.medium().eps;
    const auto kind = fluid_.particles().kind;
    Kokkos::MinMaxScalar<Real> range;
    Kokkos::parallel_reduce(
        "dvisph::coupled_output::porosity_range", Kokkos::RangePolicy<Space>(0, fluid_.size()),
        KOKKOS_LAMBDA(int i, Kokkos::MinMaxScalar<Real>& r) {
          if (kind(i) != Kind::fluid) return;
          r.min_val = math::min(r.min_val, eps(i));
          r.max_val = math::max(r.max_val, eps(i));
        },
        Kokkos::MinMax<Real>(range));
    return range;
  }

  struct BeadSums {
    double velocity_up = 0, force_up = 0;
  };
  BeadSums bead_sums() const {
    const auto& sp = beads_.spheres();
    const auto v = sp.v, f = sp.f_ext;
    const Vec<D> up = up_;
    double vel = 0, force = 0;
    Kokkos::parallel_reduce(
        "dvisph::coupled_output::bead_sums", Kokkos::RangePolicy<Space>(0, sp.n),
        KOKKOS_LAMBDA(int s, double& a, double& b) {
          for (int k = 0; k < D; ++k) a += v(s, k) * up[k], b += f(s, k) * up[k];
        },
        vel, force);
    return {vel / sp.n, force};
  }

  // The water's superficial velocity along up: sum V_i v_i.up / sum V_i over fluid
  // particles, V_i = m_i / (eps_i rho_f) the volume of mixture a particle stands for.
  double superficial_velocity_up() const {
    const auto& p = fluid_.particles();
    const auto v = p.v;
    const auto m = p.m;
    const auto kind = p.kind;
    const auto eps = fluid_.medium().eps;
    const Vec<D> up = up_;
    double flux = 0, volume = 0;
    Kokkos::parallel_reduce(
        "dvisph::coupled_output::superficial_velocity", Kokkos::RangePolicy<Space>(0, fluid_.size()),
        KOKKOS_LAMBDA(int i, double& f, double& vol) {
          if (kind(i) != Kind::fluid) return;
          const Real V = m(i) / eps(i);
          vol += V;
          for (int k = 0; k < D; ++k) f += V * v(i, k) * up[k];
        },
        flux, volume);
    return volume > 0 ? flux / volume : 0;
  }

  // Ergun (1952): -dP/dx = 150 mu (1 - eps)^2 q / (eps^3 d^2) + 1.75 rho (1 - eps) q^2 / (eps^3 d).
  double ergun_gradient(double eps, double q) const {
    const double d = s_.solids->diameter, rho = s_.density, mu = rho * s_.viscosity;
    const double e3 = eps * eps * eps;
    return 150 * mu * (1 - eps) * (1 - eps) * q / (e3 * d * d) + 1.75 * rho * (1 - eps) * q * q / (e3 * d);
  }

  std::string ergun() const {
    const auto& sp = beads_.spheres();
    auto r = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.radius);
    const double depth = D == 3 ? 1.0 : s_.solids->diameter;  // 2D: beads in a slab d deep
    double solid = 0, box = 1;
    for (int s = 0; s < sp.n; ++s) solid += 4.0 / 3.0 * math::pi * r(s) * r(s) * r(s) / depth;
    for (int k = 0; k < D; ++k) box *= s_.tank.hi[k] - s_.tank.lo[k];
    const double eps = 1 - solid / box;
    double g = 0;
    for (int k = 0; k < D; ++k) g += s_.gravity[k] * s_.gravity[k];
    const double drive = s_.density * std::sqrt(g);  // Pa/m
    const double q = q_.back();
    // Ergun's q for this drive: the positive root of ergun_gradient(eps, q) = drive, a q^2 + b q
    const double a = 0.5 * (ergun_gradient(eps, 2) - 2 * ergun_gradient(eps, 1)), b = ergun_gradient(eps, 1) - a;
    const double q_ergun = (-b + std::sqrt(b * b + 4 * a * drive)) / (2 * a);
    const std::size_t k80 = static_cast<std::size_t>(0.8 * (q_.size() - 1));
    // the spread of the porosity the water sees
    const auto seen = porosity_range();
    // the water's force on the bed per unit volume of mixture (the drive it takes up)
    const double force = -bead_sums().force_up / (box * depth);
    return fmt::format(
        ", \"bed_porosity\": {:.6g}, \"porosity_seen_min\": {:.6g}, \"porosity_seen_max\": {:.6g}, "
        "\"driving_gradient\": {:.6g}, \"superficial_velocity\": {:.6g}, "
        "\"superficial_velocity_at_80_percent\": {:.6g}, \"ergun_gradient_at_q\": {:.6g}, "
        "\"driving_over_ergun\": {:.6g}, \"ergun_superficial_velocity\": {:.6g}, "
        "\"velocity_over_ergun\": {:.6g}, \"bed_force_per_volume_along_g\": {:.6g}",
        eps, seen.min_val, seen.max_val, drive, q, q_[k80], ergun_gradient(eps, q), drive / ergun_gradient(eps, q),
        q_ergun, q / q_ergun, force);
  }

  // The porosity and the water's velocity u_f around bead 0, weighted by W_is: as the
  // drag the bead gets from each fluid particle i (proportional to 1 - eps_i).
  struct AroundBead {
    double eps = 1, u_up = 0, weight = 0;
  };
  AroundBead around_first_bead() const {
    const auto& p = fluid_.particles();
    auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
    auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.v);
    auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.kind);
    auto eps = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fluid_.medium().eps);
    auto solid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fluid_.coupling().solid_fraction());
    auto bx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), beads_.spheres().x);
    const auto& kernel = fluid_.coupling().kernel();
    AroundBead a{0, 0, 0};
    for (int i = 0; i < fluid_.size(); ++i) {
      if (kind(i) != Kind::fluid || !(solid(i) > 0)) continue;
      double r2 = 0, u = 0;
      for (int k = 0; k < D; ++k) r2 += (x(i, k) - bx(0, k)) * (x(i, k) - bx(0, k)), u += v(i, k) * up_[k];
      const double r = std::sqrt(r2);
      if (r >= kernel.radius()) continue;
      const double w = kernel.W(r);
      a.eps += w * eps(i);
      a.u_up += w * u / eps(i);
      a.weight += w;
    }
    if (a.weight > 0) a.eps /= a.weight, a.u_up /= a.weight;
    return a;
  }

  // The terminal velocity of the scene's drag law for one bead at porosity eps:
  // (rho_s - rho_f) g (1 - eps) = K(eps, u) u, by bisection.
  double law_terminal_velocity(double eps) const {
    const auto& b = *s_.solids;
    const auto& c = *s_.coupling;
    const DragLaw law(c.drag, s_.density, s_.viscosity, b.diameter, c.switch_porosity);
    double g = 0;
    for (int k = 0; k < D; ++k) g += s_.gravity[k] * s_.gravity[k];
    const double weight = std::abs(b.density - s_.density) * std::sqrt(g) * (1 - eps);
    double lo = 0, hi = 100;
    for (int it = 0; it < 200; ++it) {
      const double u = 0.5 * (lo + hi);
      (law(eps, u) * u < weight ? lo : hi) = u;
    }
    return 0.5 * (lo + hi);
  }

  std::string settling() const {
    const auto a = around_first_bead();
    const double law = law_terminal_velocity(a.eps);
    const double v_end = -velocity_up_.back();
    // the velocity at 80 % of the run: equal to the end's once the bead is terminal
    const std::size_t k80 = static_cast<std::size_t>(0.8 * (t_.size() - 1));
    const double v80 = -velocity_up_[k80];
    const double slip = v_end + a.u_up;
    return fmt::format(
        ", \"bead_velocity_end\": {:.6g}, \"bead_velocity_at_80_percent\": {:.6g}, \"t_80_percent\": "
        "{:.4g}, \"porosity_seen\": {:.5g}, \"law\": \"{}\", \"law_terminal_velocity\": {:.6g}, "
        "\"velocity_over_law\": {:.5g}, \"water_velocity_up_around_bead\": {:.5g}, "
        "\"slip_velocity\": {:.6g}, \"slip_over_law\": {:.5g}",
        v_end, v80, t_[k80], a.eps, s_.coupling->drag, law, v_end / law, a.u_up, slip, slip / law);
  }

  std::string bed_at_rest() const {
    const auto e = hydrostatic_errors<D>(fluid_, s_);
    const auto& sp = beads_.spheres();
    auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.mass);
    auto r = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), sp.radius);
    double g = 0;
    for (int k = 0; k < D; ++k) g += s_.gravity[k] * s_.gravity[k];
    g = std::sqrt(g);
    double weight = 0, buoyancy = 0;
    for (int s = 0; s < sp.n; ++s) {
      weight += m(s) * g;
      buoyancy += s_.density * 4.0 / 3.0 * math::pi * r(s) * r(s) * r(s) * g;
    }
    const double force = bead_sums().force_up;
    // fastest water (u_f = v / eps) and bead now
    const auto& p = fluid_.particles();
    const auto v = p.v;
    const auto kind = p.kind;
    const auto eps = fluid_.medium().eps;
    Real fastest = 0;
    Kokkos::parallel_reduce(
        "dvisph::coupled_output::fastest_water", Kokkos::RangePolicy<Space>(0, fluid_.size()),
        KOKKOS_LAMBDA(int i, Real& f) {
          if (kind(i) != Kind::fluid) return;
          Real v2 = 0;
          for (int k = 0; k < D; ++k) v2 += v(i, k) * v(i, k);
          f = math::max(f, math::sqrt(v2) / eps(i));
        },
        Kokkos::Max<Real>(fastest));
    return fmt::format(
        ", \"pressure_max_error_over_rho_g_H\": {:.6g}, \"pressure_rms_error_over_rho_g_H\": {:.6g}, "
        "\"pressure_particles_checked\": {}, \"water_max_speed\": {:.4g}, \"beads_max_speed\": {:.4g}, "
        "\"fluid_force_on_beads_over_buoyancy\": {:.6g}, \"floor_load_over_submerged_weight\": {:.6g}",
        e.max_over_rho_g_H, e.rms_over_rho_g_H, e.checked, fastest, beads_.max_speed(),
        force / buoyancy, (weight - force) / (weight - buoyancy));
  }

 private:
  Scene s_;
  const Solver& fluid_;
  const Beads& beads_;
  Vec<D> up_;
  double porosity_min_ = 1;
  std::vector<double> velocity_up_, t_, q_;
};

}  // namespace dvisph
