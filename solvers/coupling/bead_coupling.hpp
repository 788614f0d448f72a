#pragma once
// Two-way coupling of the water (ISPH) and the beads (DEM), method.md §2-§3,
// docs/coupling.md. Two pair loops between the particle sets, both the one neighbour
// primitive (CellSweep) with the coupling kernel W(r, h_c):
//  - at SPH particles, over the beads (fields; walls take only eps and C_r): solid fraction S_i = sum_s V_s W_is,
//    porosity eps_i = max(eps_min, 1 - S_i), solid velocity v_s,i (the V_s W_is-weighted
//    mean), C_r(eps_i), the volume ratio m_i / (eps_i rho_f V_ref) and the drag rate
//    beta_i = K(eps_i, |u_i - v_s,i|) / (eps_i rho_f) of the drag law, at the step's
//    start velocity, the mobility it gives the step dt, and the rate at which the beads
//    change the porosity where the particle stands, d eps/dt = sum_s V_s grad W_is . v_s
//    (the solids' continuity, d(1 - eps)/dt + div((1 - eps) v_s) = 0, with this step's
//    bead velocities); they fill the porous medium (solvers/isph/medium.hpp);
//  - at beads, over the fluid particles (forces): what each fluid particle i gives the
//    beads, E_i = (1 - eps_i) V_i grad P_i (the beads' buoyancy: the water keeps only
//    eps_i of its pressure force) + m_i drag_i (the reaction of the drag at the
//    corrected velocity), split among the beads by V_s W_is / S_i. The split sums to 1 over the
//    beads, so what the water gains the beads lose, to round-off. Wet wall particles
//    give (1 - eps_j) V_ref rho_f g, their hydrostatic share (momentum from the walls).
// In 2D a bead is a sphere in a slab one diameter deep: V_s is its volume over that depth
// and the force per unit depth times the depth is the bead's force.
#include "solvers/coupling/drag_law.hpp"
#include "solvers/coupling/virtual_mass.hpp"
#include "solvers/dem/spheres.hpp"
#include "solvers/isph/medium.hpp"
#include "src/core/neighbor_sweep.hpp"

namespace dvisph {

template <int D>
struct CouplingOptions {
  Real smoothing_length;  // h_c
  Real porosity_min;      // eps_min
  Real depth;             // 2D: the slab depth of a bead [m]; 3D: 1
  Real rho_f, volume;     // fluid density, V_ref = dx^D
  Vec<D> g;               // gravity: the wall's pressure gradient rho_f g (hydrostatic)
  bool porosity_rate;     // coupling.porosity_rate: d eps/dt in the PPE's source
};

template <int D, class Kernel, class Space>
class BeadCoupling {
 public:
  using memory_space = typename Space::memory_space;

  BeadCoupling(const CouplingOptions<D>& o, const DragLaw& drag, VanGentVirtualMass cr,
               const Vec<D>& bead_lo, const Vec<D>& bead_hi, unsigned periodic_axes)
      : options_(o), kernel_(o.smoothing_length), drag_(drag), cr_(cr),
        cells_(Grid<D>(bead_lo, bead_hi, kernel_.radius(), periodic_axes)) {}

  const Kernel& kernel() const { return kernel_; }
  const CouplingOptions<D>& options() const { return options_; }

  // The medium's fields at the first n SPH particles (fluid ones; walls get clear water).
  template <class X, class V, class M, class KindV>
  void fields(const dem::Spheres<D, Space>& beads, const X& x, const V& v, const M& m,
              const KindV& kind, const PorousMedium<D, Space>& medium, Real dt, int n) {
    cells_.build(beads.x, beads.n);
    const CellSweep<D, Space> sweep(cells_, beads.x, kernel_.radius());
    const auto kernel = kernel_;
    const auto drag = drag_;
    const auto cr = cr_;
    const auto o = options_;
    const auto bx = beads.v;
    const auto radius = beads.radius;
    const auto solid_out = solid_;
    const Real third = 4.0 / 3.0 * math::pi / o.depth;
    Kokkos::parallel_for(
        "dvisph::coupling::fields", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          Real solid = 0, rate = 0;
          Vec<D> vs = Vec<D>::zero();
          // walls get the porosity of the bed beside them too: the wall condition of
          // the PPE continues the water's pressure with the water's mobility
          const bool fluid = kind(i) == Kind::fluid;
          sweep.for_each(i, row<D>(x, i), [&](int s, const Vec<D>& xis, Real r) {
              const Real vol = third * radius(s) * radius(s) * radius(s);
              const Real w = vol * kernel.W(r);
              const Vec<D> grad = kernel.grad(xis, r);
              solid += w;
              for (int k = 0; k < D; ++k) {
                vs[k] += w * bx(s, k);
                rate += vol * grad[k] * bx(s, k);
              }
            });
          const bool clamped = 1 - solid < o.porosity_min;
          const Real eps = clamped ? o.porosity_min : 1 - solid;
          medium.eps_rate(i) = fluid && o.porosity_rate && !clamped ? rate : 0;
          Real slip2 = 0;
          for (int k = 0; k < D; ++k) {
            vs[k] = solid > 0 ? vs[k] / solid : 0;
            const Real u = v(i, k) / eps - vs[k];
            slip2 += u * u;
            medium.vs(i, k) = vs[k];
            medium.drag(i, k) = 0;
            medium.grad_p(i, k) = 0;
          }
          medium.eps(i) = eps;
          const Real c = 1 / cr(eps);
          medium.inv_cr(i) = c;
          medium.ratio(i) = fluid ? m(i) / (eps * o.rho_f * o.volume) : 1;
          const Real beta = fluid && solid > 0 ? drag(eps, math::sqrt(slip2)) / (eps * o.rho_f) : 0;
          medium.beta(i) = beta;
          medium.mob(i) = eps * c / (1 + dt * beta * c);
          if (!fluid)
            for (int k = 0; k < D; ++k) medium.grad_p(i, k) = o.rho_f * o.g[k];
          solid_out(i) = solid;
        });
  }

  // Forces from the water on each bead (into beads.f_ext), from the fields of this
  // step's medium; `fluid_cells` bins the SPH particles x.
  // Wet walls (role `wet(j)`) take their share too, with the hydrostatic gradient their
  // wall condition continues: a bead beside a wall or on the floor gets its whole
  // buoyancy, the walls' part of it from the walls (measured: without it the beads of
  // bed_hydrostatic got 82 % of their buoyancy).
  template <class X, class M, class KindV, class Wet>
  void forces(const dem::Spheres<D, Space>& beads, const CellList<D, Space>& fluid_cells,
              const X& x, const M& m, const KindV& kind, const Wet& wet,
              const PorousMedium<D, Space>& medium) {
    const CellSweep<D, Space> sweep(fluid_cells, x, kernel_.radius());
    const auto kernel = kernel_;
    const auto o = options_;
    const auto solid = solid_;
    const auto bx = beads.x, f = beads.f_ext;
    const auto radius = beads.radius;
    const Real third = 4.0 / 3.0 * math::pi / o.depth;
    Kokkos::parallel_for(
        "dvisph::coupling::forces", Kokkos::RangePolicy<Space>(0, beads.n), KOKKOS_LAMBDA(int s) {
          const Real vol = third * radius(s) * radius(s) * radius(s);
          Vec<D> sum = Vec<D>::zero();
          sweep.for_each(s, row<D>(bx, s), [&](int i, const Vec<D>&, Real r) {
            if (!wet(i) || !(solid(i) > 0)) return;
            const bool fluid = kind(i) == Kind::fluid;
            const Real share = vol * kernel.W(r) / solid(i);
            const Real buoyant = (1 - medium.eps(i)) * o.volume * medium.ratio(i);
            for (int k = 0; k < D; ++k)
              sum[k] += share * (buoyant * medium.grad_p(i, k) + (fluid ? m(i) * medium.drag(i, k) : 0));
          });
          for (int k = 0; k < D; ++k) f(s, k) = -o.depth * sum[k];
        });
  }

  void resize(int n) {
    if (static_cast<int>(solid_.extent(0)) < n)
      solid_ = Kokkos::View<Real*, memory_space>("dvisph::coupling::solid_fraction", n);
  }
  Kokkos::View<const Real*, memory_space> solid_fraction() const { return solid_; }
  std::size_t bytes() const { return cells_.bytes() + view_bytes(solid_); }

 private:
  CouplingOptions<D> options_;
  Kernel kernel_;
  DragLaw drag_;
  VanGentVirtualMass cr_;
  CellList<D, Space> cells_;
  Kokkos::View<Real*, memory_space> solid_;
};

// m_i *= eps_i for fluid particles (their start: a lattice inside a bed at eps rho_f).
template <class Space, class M, class Eps, class KindV>
void scale_by_porosity(const M& m, const Eps& eps, const KindV& kind, int n) {
  Kokkos::parallel_for(
      "dvisph::coupling::scale_by_porosity", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
        if (kind(i) == Kind::fluid) m(i) *= eps(i);
      });
}

}  // namespace dvisph
