#pragma once
// Stabilized ISPH (method.md §4), selective dual-velocity where numerics.alpha and
// numerics.beta differ, for clear water (the ClearWater medium: eps = 1, C_r = 1) or
// water with beads (PorousMedium: the kernels take a medium, medium.hpp; the beads' DEM
// is advanced inside the step with the water's forces, coupling/bead_coupling.hpp).
// The solver owns the particles and the step; the step is a list of stages assembled
// from the scene, so what a scene does not need (viscosity, gate, a second pressure
// solve and the transport velocity's array, the coupling) is neither allocated nor run.
#include "kernels/summation_density.hpp"
#include "solvers/coupling/bead_coupling.hpp"
#include "solvers/dem/dem_solver.hpp"
#include "solvers/isph/corrector.hpp"
#include "solvers/isph/predictor.hpp"
#include "solvers/isph/free_surface.hpp"
#include "solvers/isph/medium.hpp"
#include "solvers/isph/poisson_matrix.hpp"
#include "solvers/isph/roles.hpp"
#include "solvers/isph/settle_damping.hpp"
#include "solvers/isph/wet_cells.hpp"
#include "solvers/cell_multigrid.hpp"
#include "solvers/pcg.hpp"
#include "src/core/neighbor_list.hpp"
#include "src/numerical_error.hpp"
#include "src/checkpoint.hpp"
#include "src/core/particles.hpp"
#include "src/core/reorder.hpp"
#include "src/scene_particles.hpp"

#include <fmt/format.h>

#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace dvisph {

struct StepInfo {
  long step = 0;
  double t = 0, dt = 0;
  int cg_iterations = 0;
  double cg_residual = 0;          // relative to |b|
  double cg_density_residual = 0;  // the largest density change per step it leaves (dt^2 |r_i| / rho0)
  double max_speed = 0;        // of the physical velocity: the CFL limit
  double transport_shift = 0;  // dt max|v_transport - v| [m] (0 when alpha = beta)
};

template <int D, class Kernel, class Space = Kokkos::DefaultExecutionSpace, class Medium = ClearWater>
class IsphSolver {
 public:
  using kernel_type = Kernel;
  using execution_space = Space;
  using Beads = dem::DemSolver<D, Space>;
  using memory_space = typename Space::memory_space;
  using Sweep = typename NeighborList<D, Space>::Sweep;
  struct Stage {
    std::string name;
    std::function<void()> run;
    double seconds = 0;
  };

  // `beads`: the DEM of the scene's beads (a porous medium needs them; none for clear
  // water), advanced by the step.
  explicit IsphSolver(const Scene& s, Beads* beads = nullptr)
      : scene_(s),
        beads_(beads),
        kernel_(s.h_over_dx * s.spacing),
        volume_(std::pow(s.spacing, D)),
        rho0_(s.density),
        store_matrix_(s.pressure_operator == "stored") {
    const auto init = scene_particles<D>(s);
    n_ = static_cast<int>(init.x.size());
    domain_lo_ = init.domain_lo;
    domain_hi_ = init.domain_hi;
    for (int k = 0; k < D; ++k) g_[k] = s.gravity[k];
    walls_ = tank_walls<D>(s);
    // pressure columns: 0 for alpha (the physical velocity), 1 for beta (the transport
    // velocity) where they differ; alpha = beta: one solve, and v moves the particles
    gamma_[0] = s.alpha;
    gamma_[1] = s.beta;
    nrhs_ = s.alpha == s.beta ? 1 : 2;
    if (s.cg_preconditioner == "chebyshev") cg_.chebyshev(s.chebyshev_degree, s.chebyshev_ratio);
    if (uses_multigrid(s.cg_preconditioner)) {
      using M = CellMultigrid<D, Space>;
      multigrid_ = std::make_unique<M>(
          domain_lo_, domain_hi_, s.periodic, s.spacing, kernel_.radius(),
          s.cg_preconditioner == "additive_multigrid" ? M::FineLevel::additive : M::FineLevel::smoothed);
    }

    p_ = Particles<D, Space>(n_, "sph");
    copy_points<D>(init.x, p_.x);
    auto kind = Kokkos::create_mirror_view(p_.kind);
    auto id = Kokkos::create_mirror_view(p_.id);
    for (int i = 0; i < n_; ++i) kind(i) = init.kind[i], id(i) = i;
    Kokkos::deep_copy(p_.kind, kind);
    Kokkos::deep_copy(p_.id, id);
    Kokkos::deep_copy(p_.m, rho0_ * volume_);
    pressure_ = Kokkos::View<Real**, memory_space>("dvisph::sph::pressure", n_, nrhs_);
    rho_ = Kokkos::View<Real*, memory_space>("dvisph::sph::rho", n_);
    role_ = Kokkos::View<Role*, memory_space>("dvisph::sph::role", n_);
    invariance_ = Kokkos::View<Real*, memory_space>("dvisph::sph::invariance", n_);
    truncation_ = Kokkos::View<Real*, memory_space>("dvisph::sph::truncation", n_);
    vstar_ = Kokkos::View<Real* [D], memory_space>("dvisph::sph::vstar", n_);
    if (nrhs_ == 2) vt_ = Kokkos::View<Real* [D], memory_space>("dvisph::sph::transport_velocity", n_);
    diag_ = Kokkos::View<Real*, memory_space>("dvisph::sph::diag", n_);
    rhs_ = Kokkos::View<Real**, memory_space>("dvisph::sph::rhs", n_, nrhs_);
    kind_scratch_ = Kokkos::View<Kind*, memory_space>("dvisph::sph::kind_scratch", n_);
    id_scratch_ = Kokkos::View<int*, memory_space>("dvisph::sph::id_scratch", n_);
    cells_ = CellList<D, Space>(
        Grid<D>(domain_lo_, domain_hi_, kernel_.radius() / fluid_cells_per_radius, s.periodic));
    // every axis periodic: the pressure is defined up to a constant (the PPE is singular)
    closed_ = s.closed();
    if constexpr (is_porous<Medium>) start_coupling();
    surface_test_ = lattice_reference();
    count_kinds();
    build_stages();
    info_.dt = next_dt(0);
  }

  // One time step of method.md §4: the stages in order.
  const StepInfo& step() {
    for (auto& stage : stages_) {
      Kokkos::Profiling::pushRegion("dvisph::isph::" + stage.name);
      Kokkos::Timer timer;
      stage.run();
      Space().fence();
      stage.seconds += timer.seconds();
      Kokkos::Profiling::popRegion();
    }
    info_.t += info_.dt;
    ++info_.step;
    info_.dt = next_dt(std::max(info_.max_speed, bead_speed_));
    return info_;
  }

  const StepInfo& info() const { return info_; }
  const std::vector<Stage>& stages() const { return stages_; }
  int size() const { return n_; }
  int count(Kind k) const { return counts_[static_cast<int>(k)]; }
  const Particles<D, Space>& particles() const { return p_; }
  Kokkos::View<const Real**, memory_space> pressure() const { return pressure_; }
  Kokkos::View<const Real*, memory_space> density() const { return rho_; }
  Kokkos::View<const Role*, memory_space> roles() const { return role_; }
  // weight of the density-invariance term: 0 where the support reaches into the air
  Kokkos::View<const Real*, memory_space> invariance() const { return invariance_; }
  // how much of a fluid particle's support a free surface cuts off (roles.hpp)
  Kokkos::View<const Real*, memory_space> truncation() const { return truncation_; }
  // the step's neighbour pairs (valid after a step)
  Sweep neighbors() const { return list_.sweep(); }
  Real reference_density() const { return rho_ref_; }
  long pairs() const { return list_.pairs(); }
  // steps whose neighbour list was counted afresh (the others filled it in place)
  long neighbor_list_full_builds() const { return list_.full_builds(); }
  const Kernel& kernel() const { return kernel_; }
  const Medium& medium() const { return medium_; }
  // the coupling with the beads (porous medium only)
  const BeadCoupling<D, Kernel, Space>& coupling() const { return *coupling_; }
  const Beads& beads() const { return *beads_; }
  const CellList<D, Space>& cells() const { return cells_; }
  // Memory the solver holds in its memory space (the largest it has been), all arrays.
  std::size_t memory_bytes() const {
    return view_bytes(p_.x, p_.v, p_.m, p_.kind, p_.id, pressure_, rhs_, rho_, invariance_,
                      truncation_, diag_, role_, vstar_, vt_, kind_scratch_, id_scratch_) +
           cells_.bytes() + wet_cells_.bytes() + list_.bytes() + matrix_.bytes() + cg_.bytes() +
           (multigrid_ ? multigrid_->bytes() : 0) + coupling_bytes();
  }
  const Scene& scene() const { return scene_; }

  // The state a step reads (the particles in their current order, the pressure that
  // warm-starts CG, the clock): restoring it continues a run bit-identically.
  void save(Checkpoint& c) const {
    for_each_state_array([&](const char* name, const auto& view) { c.put(name, view); });
    c.set("sph/step", static_cast<double>(info_.step));
    c.set("sph/t", info_.t);
    c.set("sph/dt", info_.dt);
    c.set("sph/max_speed", info_.max_speed);
    c.set("sph/gate_removed", gate_removed_);
  }
  void restore(const Checkpoint& c) {
    const int n = static_cast<int>(c.extents("sph/x").at(0));
    if (n > static_cast<int>(p_.x.extent(0)))
      throw std::runtime_error("checkpoint: more particles than the scene makes");
    n_ = p_.n = n;
    for_each_state_array([&](const char* name, const auto& view) { c.get(name, view); });
    info_ = StepInfo{};
    info_.step = static_cast<long>(c.number("sph/step"));
    info_.t = c.number("sph/t");
    info_.dt = c.number("sph/dt");
    info_.max_speed = c.number("sph/max_speed");
    gate_removed_ = c.number("sph/gate_removed") != 0;
    walls_.gate = scene_.gate && !gate_removed_;
    count_kinds();
  }

 private:
  // No KOKKOS_LAMBDA in the private members: nvcc accepts device lambdas only in public
  // member functions; the kernels live in the stage functions and functors they call.

  // The per-particle arrays of the state, rows in use only (views are handles: the
  // restore writes through them).
  template <class F>
  void for_each_state_array(F&& f) const {
    const auto rows = Kokkos::make_pair(0, n_);
    f("sph/x", Kokkos::subview(p_.x, rows, Kokkos::ALL));
    f("sph/v", Kokkos::subview(p_.v, rows, Kokkos::ALL));
    f("sph/m", Kokkos::subview(p_.m, rows));
    f("sph/kind", Kokkos::subview(p_.kind, rows));
    f("sph/id", Kokkos::subview(p_.id, rows));
    f("sph/pressure", Kokkos::subview(pressure_, rows, Kokkos::ALL));
  }

  void build_stages() {
    const bool reorder = scene_.reorder_every > 0;
    if (scene_.gate) stages_.push_back({"gate", [this] { remove_gate_when_due(); }});
    if (reorder) stages_.push_back({"reorder", [this] { reorder_when_due(); }});
    stages_.push_back({"neighbors", [this] { find_neighbors(); }});
    if constexpr (is_porous<Medium>)
      stages_.push_back({"bead_fields", [this] {
                           coupling_->fields(beads_->spheres(), p_.x, p_.v, p_.m, p_.kind, medium_, info_.dt, n_);
                         }});
    stages_.push_back({"density_and_roles", [this] {
                         density_and_roles<D>(list_.sweep(), kernel_, p_.x, p_.m, p_.kind, pressure_,
                                              medium_, volume_, surface_test_, rho_, role_,
                                              invariance_, truncation_, n_);
                       }});
    stages_.push_back({scene_.viscosity > 0 ? "predictor_viscous" : "predictor", [this] {
                         predictor<D>(list_.sweep(), kernel_, p_.x, p_.v, p_.kind, medium_, g_,
                                      scene_.viscosity, scene_.no_slip, volume_, info_.dt, vstar_, n_);
                       }});
    stages_.push_back({"pressure_poisson", [this] { solve_pressure(); }});
    stages_.push_back({"corrector", [this] {
                         corrector<D>(list_.sweep(), kernel_, p_.x, vstar_, pressure_, p_.kind, role_,
                                      medium_, rho0_, volume_, info_.dt, 0, nrhs_ - 1, p_.v,
                                      transport_velocity(), n_);
                       }});
    if (scene_.settle_until > 0) stages_.push_back({"settle_damping", [this] { damp_when_settling(); }});
    if constexpr (is_porous<Medium>)
      stages_.push_back({"bead_forces", [this] {
                           coupling_->forces(beads_->spheres(), cells_, p_.x, p_.m, p_.kind,
                                             WetParticle<decltype(role_)>{role_}, medium_);
                         }});
    stages_.push_back({"move", [this] { move(); }});
    if constexpr (is_porous<Medium>)
      if (!scene_.solids->fixed) stages_.push_back({"beads", [this] { advance_beads(); }});
  }

  // Lists only for water and the walls near it (wet_cells.hpp).
  void find_neighbors() {
    cells_.build(p_.x, n_);
    const auto near_water = wet_cells_.mark(cells_.grid(), kernel_.radius(), p_.x, p_.kind, n_);
    // room in the list for the particles within a kernel radius more of the water, so
    // that most steps fill the list in place (neighbor_list.hpp)
    list_.build(CellSweep<D, Space>(cells_, p_.x, kernel_.radius()), p_.x, n_, near_water,
                [&] { return wet_cells_.wider(near_water, fluid_cells_per_radius); });
  }

  void solve_pressure() {
    const PressurePoisson<D, Sweep, Kernel, decltype(p_.x), decltype(role_), Medium> ppe{
        list_.sweep(), kernel_, p_.x, role_, volume_, full_diagonal_, walls_, medium_,
        scene_.ghost_air == "everywhere", !closed_};
    ppe.assemble(vstar_, rho_, invariance_, rho0_, rho_ref_, g_, info_.dt, gamma_, diag_, rhs_, n_);
    ppe.warm_start(pressure_, n_);
    if (closed_) remove_mean<Space>(rhs_, diag_, n_);
    // A residual r_i of the PPE leaves div v = -(dt / rho0) r_i after the corrector, a
    // density change dt^2 r_i / rho0 in one step: CG stops once no row's is above
    // numerics.cg_density_tolerance (a mean would let the few wall rows where the water
    // strikes keep theirs: the 2D impact went 0.25 dx into the wall at 1e-6).
    const Real to_density = info_.dt * info_.dt / rho0_;
    const Real max_tolerance = scene_.cg_density_tolerance / to_density;
    CgResult result;
    if (store_matrix_) {
      matrix_.build(ppe, n_);
      if (multigrid_) multigrid_->build(matrix_, diag_, p_.x, n_, nrhs_);
      result = cg_.solve(matrix_, diag_, rhs_, pressure_, n_, scene_.cg_tolerance,
                         scene_.cg_max_iterations, max_tolerance, multigrid_.get());
    } else {
      result = cg_.solve(ppe, diag_, rhs_, pressure_, n_, scene_.cg_tolerance,
                         scene_.cg_max_iterations, max_tolerance);
    }
    info_.cg_iterations = result.iterations;
    info_.cg_residual = result.residual[0];
    info_.cg_density_residual = result.max_residual[0] * to_density;
    if (!result.converged)
      throw NumericalError(fmt::format(
          "step {}, t = {:.6g} s: pressure solve not converged after {} CG iterations "
          "(relative residual {:.3g} > numerics.cg_tolerance = {:.3g})",
          info_.step, info_.t, result.iterations, result.residual[0], scene_.cg_tolerance));
  }

  void move() {
    const MoveParticles<D, Space, decltype(p_.x), decltype(p_.v), decltype(p_.kind), Medium> mover{
        p_.x, p_.v, transport_velocity(), p_.kind, medium_, info_.dt, domain_lo_, domain_hi_,
        cells_.grid().periodic, n_};
    const auto report = mover.run();
    info_.max_speed = report.max_speed;
    info_.transport_shift = info_.dt * report.max_transport_difference;
    if (report.bad >= 0) {
      auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                   Kokkos::subview(p_.x, report.bad, Kokkos::ALL));
      auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                    Kokkos::subview(p_.id, report.bad));
      std::string pos;
      for (int k = 0; k < D; ++k) pos += fmt::format("{}{:.6g}", k ? ", " : "", x(k));
      throw NumericalError(fmt::format(
          "step {}, t = {:.6g} s: fluid particle {} at ({}) m is not finite or has left the "
          "domain", info_.step, info_.t, id(), pos));
    }
  }

  void damp_when_settling() {
    if (info_.t >= scene_.settle_until) return;
    const Real factor = std::exp(-info_.dt / scene_.settle_time);
    settle_damping<D, Space>(p_.v, p_.kind, factor, n_);
    if (nrhs_ == 2) settle_damping<D, Space>(vt_, p_.kind, factor, n_);
  }

  // The beads over the fluid step, with the water's forces held (DEM sub-steps); the
  // fastest bead joins the fluid's CFL limit.
  void advance_beads() {
    try {
      beads_->advance(info_.dt);
    } catch (const std::runtime_error& e) {
      throw NumericalError(fmt::format("step {}, t = {:.6g} s: {}", info_.step, info_.t, e.what()));
    }
    bead_speed_ = beads_->max_speed();
  }

  // The porous medium's fields, the coupling, and the fluid particles' masses: a fluid
  // particle starts with m = eps rho_f V_ref, so a lattice inside a bed starts at its
  // reference density eps rho_f.
  void start_coupling() {
    if (!beads_) throw std::invalid_argument("IsphSolver: a porous medium needs beads");
    const auto& c = *scene_.coupling;
    medium_ = Medium(n_);
    CouplingOptions<D> o{c.smoothing_length > 0 ? c.smoothing_length : kernel_.h, c.porosity_min,
                      D == 3 ? 1.0 : scene_.solids->diameter, rho0_, volume_, g_, c.porosity_rate};
    coupling_.emplace(o, DragLaw(c.drag, rho0_, scene_.viscosity, scene_.solids->diameter,
                                 c.switch_porosity),
                      VanGentVirtualMass{c.virtual_mass}, beads_->box_lo(), beads_->box_hi(),
                      scene_.periodic);
    coupling_->resize(n_);
    coupling_->fields(beads_->spheres(), p_.x, p_.v, p_.m, p_.kind, medium_, 0, n_);
    scale_by_porosity<Space>(p_.m, medium_.eps, p_.kind, n_);
  }
  std::size_t coupling_bytes() const {
    if constexpr (is_porous<Medium>) return medium_.bytes() + coupling_->bytes();
    else return 0;
  }

  double next_dt(double max_speed) const {
    const double h = kernel_.h;
    double gnorm = 0;
    for (int k = 0; k < D; ++k) gnorm += g_[k] * g_[k];
    double dt = scene_.dt_max;
    if (max_speed > 0) dt = std::min(dt, scene_.cfl * h / max_speed);
    if (gnorm > 0) dt = std::min(dt, 0.25 * std::sqrt(h / std::sqrt(gnorm)));
    if (scene_.viscosity > 0) dt = std::min(dt, 0.125 * h * h / scene_.viscosity);
    if (scene_.gate && info_.t < scene_.gate->remove_at)
      dt = std::min(dt, std::max(scene_.gate->remove_at - info_.t, 1e-12));
    return dt;
  }

  // Reorders every persistent field by `perm` (its first n_new entries), using the
  // step's scratch fields as buffers (they are recomputed before use).
  void permute(const Kokkos::View<int*, memory_space>& perm, int n_new) {
    const auto keep = Kokkos::subview(perm, Kokkos::make_pair(0, n_new));
    gather_rows<Space>(vstar_, p_.x, keep);
    std::swap(p_.x, vstar_);
    gather_rows<Space>(vstar_, p_.v, keep);
    std::swap(p_.v, vstar_);
    gather_rows<Space>(rho_, p_.m, keep);
    std::swap(p_.m, rho_);
    gather_rows<Space>(rhs_, pressure_, keep);
    std::swap(pressure_, rhs_);
    gather_rows<Space>(kind_scratch_, p_.kind, keep);
    std::swap(p_.kind, kind_scratch_);
    gather_rows<Space>(id_scratch_, p_.id, keep);
    std::swap(p_.id, id_scratch_);
    n_ = p_.n = n_new;
    list_.forget_layout();
  }

  // the velocity that moves the particles: its own array only where alpha != beta
  Kokkos::View<Real* [D], memory_space> transport_velocity() const { return nrhs_ == 2 ? vt_ : p_.v; }

  void reorder_when_due() {
    if (info_.step % scene_.reorder_every != 0) return;
    cells_.build(p_.x, n_);
    permute(cells_.permutation(), n_);
  }

  void remove_gate_when_due() {
    if (gate_removed_ || info_.t < scene_.gate->remove_at) return;
    // keep every particle that is not the gate, in order
    Kokkos::View<int*, memory_space> keep("dvisph::isph::gate_keep", n_);
    const int kept = rows_not_of_kind<Space>(p_.kind, Kind::gate, n_, keep);
    permute(keep, kept);
    gate_removed_ = true;
    walls_.gate = false;
    count_kinds();
  }

  // Interior values of the initial lattice: references for the density-invariance
  // term, the density error, the free-surface tests and the ghost air.
  SurfaceTest<D> lattice_reference() {
    const auto ref = support_reference<D>(kernel_, scene_.spacing, rho0_);
    rho_ref_ = ref.rho;
    full_diagonal_ = ref.laplacian;
    return surface_test<D>(scene_, ref);
  }

  void count_kinds() {
    counts_.assign(4, 0);
    auto kind = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                    Kokkos::subview(p_.kind, Kokkos::make_pair(0, n_)));
    for (int i = 0; i < n_; ++i) ++counts_[static_cast<int>(kind(i))];
  }

  Scene scene_;
  Kernel kernel_;
  Beads* beads_ = nullptr;
  double bead_speed_ = 0;  // the fastest bead after the step: it joins the CFL limit
  Medium medium_;
  std::optional<BeadCoupling<D, Kernel, Space>> coupling_;
  Real volume_, rho0_, rho_ref_ = 0;
  SurfaceTest<D> surface_test_;
  Real full_diagonal_ = 0;
  TankWalls<D> walls_;
  Vec<D> g_, domain_lo_, domain_hi_;
  Real gamma_[max_rhs];
  int nrhs_ = 1;
  int n_ = 0;
  bool gate_removed_ = false;
  bool closed_ = false;  // all axes periodic: the PPE's right-hand side loses its mean
  bool store_matrix_;
  std::vector<int> counts_;

  Particles<D, Space> p_;
  Kokkos::View<Real**, memory_space> pressure_, rhs_;
  Kokkos::View<Real*, memory_space> rho_, invariance_, truncation_, diag_;
  Kokkos::View<Role*, memory_space> role_;
  Kokkos::View<Real* [D], memory_space> vstar_, vt_;
  Kokkos::View<Kind*, memory_space> kind_scratch_;
  Kokkos::View<int*, memory_space> id_scratch_;

  CellList<D, Space> cells_;
  WetCells<D, Space> wet_cells_;
  NeighborList<D, Space> list_;
  PoissonMatrix<Space> matrix_;  // only filled when the scene stores the PPE matrix
  ConjugateGradient<Space> cg_;
  std::unique_ptr<CellMultigrid<D, Space>> multigrid_;  // numerics.cg_preconditioner: multigrid
  std::vector<Stage> stages_;
  StepInfo info_;
};

}  // namespace dvisph
