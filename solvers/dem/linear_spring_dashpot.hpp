#pragma once
// Linear spring-dashpot contact with Coulomb friction (Cundall & Strack 1979), the DEM
// contact law of method.md §3. Normal: F_n = k_n d + eta_n dd/dt along the normal, d the
// overlap, eta_n = 2 zeta sqrt(m* k_n) with zeta from e and m* the contact's reduced
// mass (so beads of any size get the same e). Tangential: a spring on the tangential
// displacement xi accumulated over the contact, a dashpot with the same damping ratio,
// and the Coulomb limit |F_t| <= mu max(F_n, 0).
//
// The contact acts exactly while d > 0 and F_n is not clamped to be non-attractive: the
// dashpot pulls while the beads separate, and then the normal motion is the damped
// oscillator whose half period ends at d = 0 with rebound speed e times the impact
// speed, the textbook relation behind eta_n. Clamping F_n >= 0 drops that pull, less is
// dissipated and the rebound comes out faster than e says: by 10 % at e = 0.5, 0.2 % at
// e = 0.9 (option `non_attractive`, measured in tests/tst_dem.cpp).
//
// Time discretization: in velocity Verlet a force sampled at t acts over the kick
// interval [t - dt/2, t + dt/2], and the overlap follows the drifts piecewise linearly
// (back with the half-step velocity, forward with the predicted one). The contact starts
// and ends inside an interval, where the dashpot force jumps; sampling it at t would
// make an O(dt) error in e (several per cent at t_c/25). Here the dashpot impulse is
// eta_n times the change of the positive part of d over the interval (exact for any
// start time), the spring uses the mean of the positive part over an interval that holds
// the start or end and its value at t otherwise, and the tangential force acts for the
// fraction of the interval in contact. Inside a contact this is velocity Verlet with the
// dashpot evaluated at the predicted synchronous velocity, second order in dt.
#include "src/core/types.hpp"

#include <cmath>
#include <stdexcept>

namespace dvisph::dem {

// Overlap of a contact at the drift and kick boundaries around the force sample t,
// given the normal separation rate v_n = -dd/dt before and after t.
struct Overlaps {
  Real prev, lo, now, hi;  // at t - dt, t - dt/2, t, t + dt/2

  KOKKOS_INLINE_FUNCTION static Overlaps along(Real now, Real vn_before, Real vn_after, Real dt) {
    return {now + dt * vn_before, now + 0.5 * dt * vn_before, now, now - 0.5 * dt * vn_after};
  }
  // (| rather than ||: one test, not three branches)
  KOKKOS_INLINE_FUNCTION bool touching() const { return (lo > 0) | (now > 0) | (hi > 0); }
  // In contact over the whole kick interval (most contacts in a bed): the law's
  // fractions are 1 and its means plain values (no division needed for them).
  KOKKOS_INLINE_FUNCTION bool interior() const { return lo > 0 && now > 0 && hi > 0; }

  // Fraction of a linear segment from a to b where it is positive.
  KOKKOS_INLINE_FUNCTION static Real positive_fraction(Real a, Real b) {
    if (a > 0 && b > 0) return 1;
    if (a <= 0 && b <= 0) return 0;
    return math::max(a, b) / math::abs(a - b);
  }
  // Mean of the positive part of a linear segment from a to b.
  KOKKOS_INLINE_FUNCTION static Real positive_mean(Real a, Real b) {
    if (a > 0 && b > 0) return 0.5 * (a + b);
    if (a <= 0 && b <= 0) return 0;
    const Real p = math::max(a, b);
    return 0.5 * p * p / math::abs(a - b);
  }
};

// One contact as the law sees it. Velocities are those of the particle's contact point
// relative to the partner's, over the drift before t and (predicted) after t.
template <int D>
struct Contact {
  Overlaps overlap;
  Vec<D> normal;  // unit, from the partner to the particle
  Vec<D> v_before, v_after;
  Real sqrt_m;  // square root of the reduced mass m_i m_j / (m_i + m_j), or of m_i against a wall
};

template <int D>
struct ContactResponse {
  Vec<D> force;  // on the particle
  Vec<D> xi;     // tangential displacement at t
};

template <int D>
struct LinearSpringDashpot {
  static constexpr const char* name = "linear_spring_dashpot";
  Real k_n;   // normal stiffness [N/m]
  Real k_t;   // tangential stiffness [N/m]; 2/7 k_n makes the tangential and normal
              // oscillations of a sphere equally fast
  Real mu;    // Coulomb friction coefficient
  Real e;     // normal restitution coefficient
  Real zeta;  // damping ratio from e
  bool non_attractive = false;  // clamp F_n >= 0 (changes e, see above)
  Real eta_n_unit, eta_t_unit;  // the dashpots per sqrt(kg): one square root per contact

  LinearSpringDashpot(Real k_normal, Real restitution, Real friction)
      : k_n(k_normal), k_t(2.0 / 7.0 * k_normal), mu(friction), e(restitution) {
    if (!(k_n > 0)) throw std::invalid_argument("LinearSpringDashpot: k_n must be > 0");
    if (!(e > 0 && e <= 1)) throw std::invalid_argument("LinearSpringDashpot: e must be in (0, 1]");
    if (!(mu >= 0)) throw std::invalid_argument("LinearSpringDashpot: mu must be >= 0");
    const Real le = std::log(e);
    zeta = -le / std::sqrt(math::pi * math::pi + le * le);
    eta_n_unit = 2 * zeta * std::sqrt(k_n);
    eta_t_unit = 2 * zeta * std::sqrt(k_t);
  }

  KOKKOS_INLINE_FUNCTION Real eta_n(Real m_eff) const { return eta_n_unit * math::sqrt(m_eff); }
  // Same damping ratio on the tangential spring.
  KOKKOS_INLINE_FUNCTION Real eta_t(Real m_eff) const { return eta_t_unit * math::sqrt(m_eff); }

  // Duration of a binary collision: half a period of the damped normal oscillation.
  Real contact_time(Real m_eff) const {
    const Real damp = eta_n(m_eff) / (2 * m_eff);
    return math::pi / std::sqrt(k_n / m_eff - damp * damp);
  }

  // Elastic energy stored at overlap d and tangential displacement xi.
  KOKKOS_INLINE_FUNCTION Real energy(Real d, const Vec<D>& xi) const {
    const Real dp = math::max(d, 0);
    return 0.5 * k_n * dp * dp + 0.5 * k_t * dot(xi, xi);
  }

  // Force over the kick interval around t, and the tangential displacement at t from
  // its value xi_old at t - dt. Call only for c.overlap.touching(). (Forced inline: GCC
  // calls it otherwise, and the pair stage of the bead-bed settle takes 10 % longer.)
  KOKKOS_FORCEINLINE_FUNCTION ContactResponse<D> operator()(const Contact<D>& c, const Vec<D>& xi_old,
                                                            Real dt) const {
    const Overlaps& d = c.overlap;
    const Vec<D>& n = c.normal;
    const bool interior = d.interior();
    const Real d_spring =
        interior
            ? d.now
            : 0.5 * (Overlaps::positive_mean(d.lo, d.now) + Overlaps::positive_mean(d.now, d.hi));
    const Real sqrt_m = c.sqrt_m;
    Real fn = k_n * d_spring + eta_n_unit * sqrt_m * (math::max(d.hi, 0) - math::max(d.lo, 0)) / dt;
    if (non_attractive) fn = math::max(fn, 0);

    // Tangential displacement: the old one projected onto the current tangent plane, as
    // LAMMPS and LIGGGHTS do, plus the tangential drift while in contact. The projection
    // shortens it by a factor cos(theta) at most, for a normal that turns by theta in a
    // step (theta < 0.05 rad under the skin's bound on a step's move); a rescale to the
    // old length, sqrt(|xi_old|^2 / |xi|^2), took 7 % of the bead-bed settle's contact
    // pass (benchmarks/RESULTS.md, issue 17).
    Vec<D> xi = tangential(xi_old, n);
    xi += (Overlaps::positive_fraction(d.prev, d.now) * dt) * tangential(c.v_before, n);

    // Tangential force while in contact, limited by the normal force while in contact.
    // Sliding (the spring alone would pass the limit): the spring gives way to hold
    // exactly the limit and the dashpot is off. Shrinking xi only, never stretching it
    // (as the common xi = -(F_t + eta_t v_t)/k_t can when the dashpot dominates), keeps
    // the limit from storing energy in the spring. Lengths are compared squared, so a
    // contact that sticks takes no square root here.
    const Real in_contact =
        interior ? 1
                 : 0.5 * (Overlaps::positive_fraction(d.lo, d.now) + Overlaps::positive_fraction(d.now, d.hi));
    // Only compression presses the surfaces together: while the dashpot pulls (fn < 0)
    // there is no friction to hold.
    const Real limit = interior ? mu * math::max(fn, 0) : mu * math::max(fn, 0) / in_contact,
               limit2 = limit * limit;
    const Real xi2 = dot(xi, xi);
    Vec<D> ft;
    if (k_t * k_t * xi2 > limit2) {
      xi = (limit / (k_t * math::sqrt(xi2))) * xi;
      ft = (-k_t) * xi;
    } else {
      ft = (-k_t) * xi + (-eta_t_unit * sqrt_m) * tangential(0.5 * (c.v_before + c.v_after), n);
      const Real ft2 = dot(ft, ft);
      if (ft2 > limit2) ft = (limit / math::sqrt(ft2)) * ft;
    }
    return {fn * n + in_contact * ft, xi};
  }

 private:
  KOKKOS_FORCEINLINE_FUNCTION static Vec<D> tangential(const Vec<D>& a, const Vec<D>& n) {
    return a - dot(a, n) * n;
  }
};

}  // namespace dvisph::dem
