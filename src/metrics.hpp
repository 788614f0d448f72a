#pragma once
// Figures a run reports while it goes (series.csv) and at its end (summary.json).
#include "solvers/isph/roles.hpp"
#include "solvers/isph/tank_walls.hpp"
#include "src/scene.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace dvisph {

// Largest first coordinate of a fluid particle: the surge front.
template <class Space, class X, class KindV>
Real front_position(const X& x, const KindV& kind, int n) {
  Real front = -1e300;
  Kokkos::parallel_reduce(
      "dvisph::metrics::front", Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i, Real& m) {
        if (kind(i) == Kind::fluid && x(i, 0) > m) m = x(i, 0);
      },
      Kokkos::Max<Real>(front));
  return front;
}

// How far the deepest fluid particle centre lies inside the tank's walls (0 if none).
template <int D, class Space, class X, class KindV>
Real wall_penetration(const X& x, const KindV& kind, int n, const TankWalls<D>& walls) {
  Real depth = 0;
  Kokkos::parallel_reduce(
      "dvisph::metrics::wall_penetration", Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i, Real& m) {
        if (kind(i) == Kind::fluid) m = math::max(m, walls.depth_inside(row<D>(x, i)));
      },
      Kokkos::Max<Real>(depth));
  return depth;
}

// Submerged: the paper's density error counts particles with P >= 100 Pa
// ("near-surface particles excluded"). Particles whose support reaches well into the
// air are left out too (the solver's invariance weight is 0: on the surface, or div r
// at most 0.9 of its interior value): in a fast flow some carry 100 Pa, e.g. on the
// open face of a collapsing column beside a wall, and their summation density lacks the
// empty part of their support (10-18 % below rho0), which is not a density error.
constexpr Real submerged_pressure = 100;  // Pa
KOKKOS_INLINE_FUNCTION bool submerged(Real invariance_weight, Real p) {
  return invariance_weight > 0 && p >= submerged_pressure;
}

// Largest |<rho> - rho_ref| / rho_ref over submerged fluid particles (0 if none).
template <class Space, class Rho, class P, class Weight>
Real max_density_error(const Rho& rho, const P& p, const Weight& invariance, Real rho_ref, int n) {
  Real err = 0;
  Kokkos::parallel_reduce(
      "dvisph::metrics::density_error", Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i, Real& m) {
        if (!submerged(invariance(i), p(i, 0))) return;
        const Real e = math::abs(rho(i) - rho_ref) / rho_ref;
        if (e > m) m = e;
      },
      Kokkos::Max<Real>(err));
  return math::max(err, 0);
}

// 95th percentile of |<rho> - rho_ref| / rho_ref over the same particles (0 if none),
// from a histogram with 100 logarithmic bins per decade on [1e-6, 1): the upper edge of
// the bin that holds it, within 2.3 %. The bins are allocated once: a run asks every
// series row.
template <class Space>
class DensityErrorP95 {
 public:
  static constexpr int per_decade = 100, decades = 6, bins = per_decade * decades;
  static constexpr Real smallest = 1e-6;

  template <class Rho, class P, class Weight>
  Real operator()(const Rho& rho, const P& p, const Weight& invariance, Real rho_ref, int n) const {
    const auto count = count_;
    Kokkos::deep_copy(count, 0);
    Kokkos::parallel_for(
        "dvisph::metrics::density_error_histogram", Kokkos::RangePolicy<Space>(0, n),
        KOKKOS_LAMBDA(int i) {
          if (!submerged(invariance(i), p(i, 0))) return;
          const Real e = math::abs(rho(i) - rho_ref) / rho_ref;
          const Real b = e > smallest ? per_decade * math::log(e / smallest) / math::log(10.0) : 0;
          Kokkos::atomic_increment(&count(b < bins - 1 ? static_cast<int>(b) : bins - 1));
        });
    Kokkos::deep_copy(host_, count);
    long total = 0;
    for (int b = 0; b < bins; ++b) total += host_(b);
    long below = 0;
    for (int b = 0; b < bins; ++b) {
      below += host_(b);
      if (below >= 0.95 * total && total > 0) return smallest * std::pow(10.0, (b + 1.0) / per_decade);
    }
    return 0;
  }

 private:
  Kokkos::View<int*, typename Space::memory_space> count_{"dvisph::metrics::density_error_bins", bins};
  typename Kokkos::View<int*, typename Space::memory_space>::HostMirror host_ =
      Kokkos::create_mirror_view(count_);
};

// Sweeps over the stored neighbour pairs that one ISPH step makes besides its CG
// iterations (one mat-vec each), from the names of its stages (isph_solver.hpp): the
// list build meets every pair twice (count, fill), the pressure stage sweeps to assemble
// and for the initial residual, the density, viscous predictor and corrector once each.
// Rows that do no work (walls away from water) are counted too: an upper bound.
template <class Stages>
int pair_sweeps_outside_cg(const Stages& stages) {
  int sweeps = 0;
  for (const auto& st : stages) {
    if (st.name == "neighbors" || st.name == "pressure_poisson") sweeps += 2;
    if (st.name == "density_and_roles" || st.name == "predictor_viscous" || st.name == "corrector")
      sweeps += 1;
  }
  return sweeps;
}

// Martin & Moyce (1952) surge front, Z = z/a against T = t sqrt(2g/a).
struct FrontData {
  std::vector<double> T, Z;
};
inline FrontData martin_moyce() {
  FrontData d;
  std::ifstream in(std::string(DVISPH_SOURCE_DIR) + "/data/martin_moyce_1952.csv");
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#' || line[0] == 'T') continue;
    std::stringstream ss(line);
    double t, z;
    char comma;
    if (ss >> t >> comma >> z) d.T.push_back(t), d.Z.push_back(z);
  }
  return d;
}

// RMS of (Z_sim(T - lag) - Z_data(T)) / Z_data(T) over data points with T in
// [t_lo, t_hi], the simulated front interpolated linearly in T. Returns -1 if no
// point is covered.
inline double front_rms_deviation(const FrontData& sim, const FrontData& data, double t_lo,
                                  double t_hi, int* points = nullptr, double lag = 0) {
  double sum = 0;
  int count = 0;
  for (std::size_t k = 0; k < data.T.size(); ++k) {
    if (data.T[k] < t_lo || data.T[k] > t_hi) continue;
    const double T = data.T[k] - lag;
    for (std::size_t s = 1; s < sim.T.size(); ++s)
      if (sim.T[s - 1] <= T && T <= sim.T[s]) {
        const double w = (T - sim.T[s - 1]) / (sim.T[s] - sim.T[s - 1]);
        const double z = (1 - w) * sim.Z[s - 1] + w * sim.Z[s];
        sum += (z - data.Z[k]) * (z - data.Z[k]) / (data.Z[k] * data.Z[k]);
        ++count;
        break;
      }
  }
  if (points) *points = count;
  return count ? std::sqrt(sum / count) : -1;
}

// The time lag (in T, within +-1) that minimises the deviation: how much of the
// deviation is a shift in time, as from the gate opening in the experiment.
inline double best_front_lag(const FrontData& sim, const FrontData& data, double t_lo, double t_hi) {
  double best = 0, best_rms = 1e300;
  for (double lag = -1; lag <= 1; lag += 0.005) {
    int points = 0, all = 0;
    front_rms_deviation(sim, data, t_lo, t_hi, &all);
    const double rms = front_rms_deviation(sim, data, t_lo, t_hi, &points, lag);
    if (points == all && rms >= 0 && rms < best_rms) best_rms = rms, best = lag;
  }
  return best;
}

// Pressure against rho g (H - y) over fluid particles at least two layers below the
// still-water height H (metrics.water_height).
struct HydrostaticErrors {
  double max_over_rho_g_H = 0, rms_over_rho_g_H = 0, max_pointwise = 0;
  int checked = 0;
};

template <int D, class Solver>
HydrostaticErrors hydrostatic_errors(const Solver& solver, const Scene& s) {
  const auto& p = solver.particles();
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.x);
  auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), p.kind);
  auto pr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), solver.pressure());
  const double g = std::abs(s.gravity[D - 1]), H = s.water_height, rg = s.density * g;
  HydrostaticErrors e;
  double sum2 = 0;
  for (int i = 0; i < solver.size(); ++i) {
    if (kind(i) != Kind::fluid) continue;
    const double y = x(i, D - 1);
    if (y > H - 2 * s.spacing) continue;
    const double exact = rg * (H - y), err = std::abs(pr(i, 0) - exact);
    e.max_over_rho_g_H = std::max(e.max_over_rho_g_H, err / (rg * H));
    e.max_pointwise = std::max(e.max_pointwise, err / exact);
    sum2 += err * err;
    ++e.checked;
  }
  e.rms_over_rho_g_H = std::sqrt(sum2 / std::max(e.checked, 1)) / (rg * H);
  return e;
}

}  // namespace dvisph
