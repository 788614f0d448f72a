#pragma once
// What a fluid particle's equations take from the solids around it (method.md §2, eq. 5,
// docs/coupling.md): every ISPH kernel reads it through a medium, so one source serves
// clear water and beds. The particles carry the superficial velocity v = eps u_f.
//   porosity(i)             eps_i (1 for wall particles)
//   volume_ratio(j)         V_j / V_ref, V_j = m_j / (eps_j rho_f), V_ref = dx^D
//   inverse_virtual_mass(i) 1 / C_r,i: a fluid particle accelerates as if C_r times heavier
//   mobility(i)             eps_i / C_r,i / (1 + dt beta_i / C_r,i): the fluid's share of
//                           a pressure gradient is eps grad P (the rest, (1 - eps) V grad P,
//                           is the beads' buoyancy: coupling/bead_coupling.hpp), and the
//                           drag is implicit in the pressure's correction as in the
//                           predictor's, so v = v* - dt mobility / rho_f grad P
//   porosity_rate(i)        d eps/dt at the particle's place from the beads' motion: the
//                           water's continuity is d eps/dt + div v = 0, so the PPE's source
//                           is div v* + d eps/dt (0 with coupling.porosity_rate: false;
//                           a bed's only: the PPE adds nothing for clear water)
//   pair_coefficient(i, j)  the PPE's symmetric pair coefficient, the harmonic mean of the
//                           two mobilities (one that depends on i and j alike keeps the
//                           PPE matrix symmetric)
//   predict(i, v, a, dt)    v* = v + dt a, a = (eps / C_r)(g + nu lap v); in a bed with the
//                           drag -beta (v/eps - v_s) per unit mass, implicit
//   keep_corrected(i, grad P, v)  the corrector's grad P_i (the beads' buoyancy) and the drag
//                           at the corrected velocity v (their drag's reaction). Taking the
//                           drag at v* instead, which holds a step of gravity that the
//                           pressure has not yet balanced, cost the beads of a bed at rest
//                           2 % of their buoyancy and let a settling bead fall 5 % fast
// Clear water is the medium whose values are the constants eps = 1, C_r = 1, so a
// water-only scene holds and reads no such fields, and multiplying by them is exact:
// clear-water results are bit-identical to a solver without media.
#include "src/core/types.hpp"

namespace dvisph {

struct ClearWater {
  static constexpr bool porous = false;
  KOKKOS_INLINE_FUNCTION Real porosity(int) const { return 1; }
  KOKKOS_INLINE_FUNCTION Real volume_ratio(int) const { return 1; }
  KOKKOS_INLINE_FUNCTION Real pair_coefficient(int, int) const { return 1; }
  KOKKOS_INLINE_FUNCTION Real inverse_virtual_mass(int) const { return 1; }
  KOKKOS_INLINE_FUNCTION Real mobility(int) const { return 1; }
  template <int D>
  KOKKOS_INLINE_FUNCTION Vec<D> predict(int, const Vec<D>& v, const Vec<D>& a, Real dt) const {
    Vec<D> out;
    for (int k = 0; k < D; ++k) out[k] = v[k] + dt * a[k];
    return out;
  }
  template <int D>
  KOKKOS_INLINE_FUNCTION void keep_corrected(int, const Vec<D>&, const Vec<D>&) const {}
};

// A bed: the per-particle fields, filled each step by the coupling (bead_coupling.hpp)
// before any kernel reads them.
template <int D, class Space>
struct PorousMedium {
  static constexpr bool porous = true;
  using memory_space = typename Space::memory_space;
  Kokkos::View<Real*, memory_space> eps, ratio, inv_cr, mob;
  Kokkos::View<Real*, memory_space> eps_rate;  // d eps/dt [1/s]
  Kokkos::View<Real*, memory_space> beta;  // drag per unit mass over the slip [1/s]
  Kokkos::View<Real* [D], memory_space> vs;          // solid velocity at the particle
  Kokkos::View<Real* [D], memory_space> drag;        // drag per unit mass applied [m/s^2]
  Kokkos::View<Real* [D], memory_space> grad_p;      // grad P of the physical pressure

  PorousMedium() = default;
  explicit PorousMedium(int n)
      : eps("dvisph::medium::eps", n),
        ratio("dvisph::medium::volume_ratio", n),
        inv_cr("dvisph::medium::inverse_virtual_mass", n),
        mob("dvisph::medium::mobility", n),
        eps_rate("dvisph::medium::porosity_rate", n),
        beta("dvisph::medium::drag_rate", n),
        vs("dvisph::medium::solid_velocity", n),
        drag("dvisph::medium::drag", n),
        grad_p("dvisph::medium::grad_p", n) {}

  KOKKOS_INLINE_FUNCTION Real porosity(int i) const { return eps(i); }
  KOKKOS_INLINE_FUNCTION Real volume_ratio(int j) const { return ratio(j); }
  KOKKOS_INLINE_FUNCTION Real inverse_virtual_mass(int i) const { return inv_cr(i); }
  KOKKOS_INLINE_FUNCTION Real mobility(int i) const { return mob(i); }
  KOKKOS_INLINE_FUNCTION Real porosity_rate(int i) const { return eps_rate(i); }
  KOKKOS_INLINE_FUNCTION Real pair_coefficient(int i, int j) const {
    const Real a = mobility(i), b = mobility(j);
    return 2 * a * b / (a + b);
  }
  // v* (1 + dt beta / C_r) = v + dt a + dt (eps / C_r) beta v_s: the drag is implicit,
  // so a stiff bed (beta dt >> 1) brings the water to the beads' velocity, not past it;
  // with the pressure's correction at the mobility above, the step is
  // v_new = v + dt a + dt (eps / C_r) (drag(v_new) - grad P / rho_f)
  KOKKOS_INLINE_FUNCTION Vec<D> predict(int i, const Vec<D>& v, const Vec<D>& a, Real dt) const {
    const Real b = beta(i), e = eps(i), c = inv_cr(i);
    Vec<D> out;
    for (int k = 0; k < D; ++k) out[k] = (v[k] + dt * (a[k] + e * c * b * vs(i, k))) / (1 + dt * b * c);
    return out;
  }
  KOKKOS_INLINE_FUNCTION void keep_corrected(int i, const Vec<D>& g, const Vec<D>& v) const {
    const Real b = beta(i), e = eps(i);
    for (int k = 0; k < D; ++k) {
      grad_p(i, k) = g[k];
      drag(i, k) = -b * (v[k] / e - vs(i, k));
    }
  }
  std::size_t bytes() const { return view_bytes(eps, ratio, inv_cr, mob, eps_rate, beta, vs, drag, grad_p); }
};

template <class Medium>
inline constexpr bool is_porous = Medium::porous;

}  // namespace dvisph
