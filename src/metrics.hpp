#pragma once
// Figures a run reports while it goes (series.csv) and at its end (summary.json).
#include "solvers/isph/roles.hpp"
#include "solvers/isph/tank_walls.hpp"
#include "src/connected_front.hpp"
#include "src/scene.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace dvisph {

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

// The density error the paper reports (method.md §5): |<rho> - rho_ref| / rho_ref over
// submerged fluid particles (P >= 100 Pa) with near-surface particles excluded. Near
// the surface: a free-surface particle (truncation >= 0.5, half a flat face's; roles.hpp)
// lies within the kernel support, the particle itself included. What is counted then
// has a full support, so its deviation from rho_ref is a density error and not a
// missing part of the support; over- and under-density count alike. Both criteria are
// geometric and fixed here, independent of the solver's knobs.
// The rule before (P >= 100 Pa and the solver's invariance weight > 0, so expanded
// water whose weight had dropped to 0 went uncounted) is kept for one release as
// `weighted_rule`, so that the change of figures is visible.
// In a bed the reference is eps_i rho_ref (the medium's porosity).
constexpr Real submerged_pressure = 100;  // Pa
constexpr Real surface_truncation = 0.5;

struct DensityErrorFigures {
  Real max = 0, p50 = 0, p95 = 0, p99 = 0;  // 0 if no particle is counted
  long counted = 0;
};

// Percentiles from a histogram with 100 logarithmic bins per decade on [1e-6, 1): the
// upper edge of the bin that holds each, within 2.3 %; the max exact. The arrays are
// allocated once and grow with the particle count: a run asks every series row.
template <class Space>
class DensityError {
 public:
  static constexpr int per_decade = 100, decades = 6, bins = per_decade * decades;
  static constexpr Real smallest = 1e-6;

  template <int D, class Sweep, class KindV, class Rho, class P, class Truncation, class Medium = ClearWater>
  DensityErrorFigures paper_rule(const Sweep& sweep, const KindV& kind, const Rho& rho, const P& p,
                                 const Truncation& truncation, Real rho_ref, int n,
                                 const Medium& medium = {}) {
    const auto err = scratch(n);
    Kokkos::parallel_for(
        "dvisph::metrics::density_error", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          err(i) = -1;
          if (kind(i) != Kind::fluid || p(i, 0) < submerged_pressure) return;
          bool near_surface = false;
          sweep.for_each(i, row<D>(sweep.x, i), [&](int j, const Vec<D>&, Real) {
            if (kind(j) == Kind::fluid && truncation(j) >= surface_truncation) near_surface = true;
          });
          const Real ref = rho_ref * medium.porosity(i);
          if (!near_surface) err(i) = math::abs(rho(i) - ref) / ref;
        });
    return figures(n);
  }

  template <class KindV, class Rho, class P, class Weight, class Medium = ClearWater>
  DensityErrorFigures weighted_rule(const KindV& kind, const Rho& rho, const P& p,
                                    const Weight& invariance, Real rho_ref, int n,
                                    const Medium& medium = {}) {
    const auto err = scratch(n);
    Kokkos::parallel_for(
        "dvisph::metrics::density_error_weighted_rule", Kokkos::RangePolicy<Space>(0, n),
        KOKKOS_LAMBDA(int i) {
          const bool counted = kind(i) == Kind::fluid && invariance(i) > 0 && p(i, 0) >= submerged_pressure;
          const Real ref = rho_ref * medium.porosity(i);
          err(i) = counted ? math::abs(rho(i) - ref) / ref : -1;
        });
    return figures(n);
  }

  // Counts per bin of the rule applied last (after its figures), and bin b's edges:
  // [smallest 10^(b / per_decade), smallest 10^((b + 1) / per_decade)), the first bin
  // from 0, the last to infinity.
  std::vector<long> histogram() const {
    std::vector<long> h(bins);
    for (int b = 0; b < bins; ++b) h[b] = host_(b);
    return h;
  }
  static Real bin_lower(int b) { return b == 0 ? 0 : smallest * std::pow(10.0, Real(b) / per_decade); }

  // The figures of the rule applied last, over its first n particles. (Public, as every
  // member function with a device lambda: nvcc accepts no others.)
  DensityErrorFigures figures(int n) const {
    const auto err = err_;
    const auto count = count_;
    Kokkos::deep_copy(count, 0);
    DensityErrorFigures f;
    Kokkos::parallel_reduce(
        "dvisph::metrics::density_error_histogram", Kokkos::RangePolicy<Space>(0, n),
        KOKKOS_LAMBDA(int i, Real& m) {
          const Real e = err(i);
          if (e < 0) return;
          const Real b = e > smallest ? per_decade * math::log(e / smallest) / math::log(10.0) : 0;
          Kokkos::atomic_increment(&count(b < bins - 1 ? static_cast<int>(b) : bins - 1));
          if (e > m) m = e;
        },
        Kokkos::Max<Real>(f.max));
    f.max = math::max(f.max, 0);
    Kokkos::deep_copy(host_, count);
    for (int b = 0; b < bins; ++b) f.counted += host_(b);
    long below = 0;
    Real* targets[3] = {&f.p50, &f.p95, &f.p99};
    const double fractions[3] = {0.5, 0.95, 0.99};
    int next = 0;
    for (int b = 0; b < bins && next < 3 && f.counted > 0; ++b) {
      below += host_(b);
      while (next < 3 && below >= fractions[next] * f.counted)
        *targets[next++] = smallest * std::pow(10.0, (b + 1.0) / per_decade);
    }
    return f;
  }

 private:
  Kokkos::View<Real*, typename Space::memory_space> scratch(int n) {
    if (static_cast<int>(err_.extent(0)) < n) err_ = decltype(err_)("dvisph::metrics::density_error", n);
    return err_;
  }

  Kokkos::View<Real*, typename Space::memory_space> err_;
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

// (Z_sim(T - lag) - Z_data(T)) / Z_data(T) at each data point with T in [t_lo, t_hi]
// that the simulated front covers (interpolated linearly in T), in the data's order.
inline std::vector<double> front_deviations(const FrontData& sim, const FrontData& data, double t_lo,
                                            double t_hi, double lag = 0) {
  std::vector<double> dev;
  for (std::size_t k = 0; k < data.T.size(); ++k) {
    if (data.T[k] < t_lo || data.T[k] > t_hi) continue;
    const double T = data.T[k] - lag;
    for (std::size_t s = 1; s < sim.T.size(); ++s)
      if (sim.T[s - 1] <= T && T <= sim.T[s]) {
        const double w = (T - sim.T[s - 1]) / (sim.T[s] - sim.T[s - 1]);
        const double z = (1 - w) * sim.Z[s - 1] + w * sim.Z[s];
        dev.push_back((z - data.Z[k]) / data.Z[k]);
        break;
      }
  }
  return dev;
}

// Their RMS; -1 if no point is covered.
inline double front_rms_deviation(const FrontData& sim, const FrontData& data, double t_lo,
                                  double t_hi, int* points = nullptr, double lag = 0) {
  const auto dev = front_deviations(sim, data, t_lo, t_hi, lag);
  double sum = 0;
  for (const double d : dev) sum += d * d;
  if (points) *points = static_cast<int>(dev.size());
  return dev.empty() ? -1 : std::sqrt(sum / dev.size());
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
