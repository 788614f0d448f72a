#pragma once
// DEM for the glass beads (method.md §3): spheres, plane walls, the linear spring-dashpot
// law with Coulomb friction, gravity and an external force per bead held over a fluid
// step. Velocity Verlet: half kick, drift, contact forces, half kick. Contacts are taken
// from a Verlet list (src/core/neighbor_list.hpp) of the pairs within the contact search
// radius plus a list skin, built from a cell list and rebuilt only once some bead has
// moved more than half the list skin since the last build, so no pair that can touch is
// missing; binning and searching every step cost 3.8x LIGGGHTS' time on the bead-bed
// settle. Each pair is evaluated once, by its lower index; the other bead gathers it in
// a fixed order (src/core/half_pairs.hpp), in a second kernel where beads run in parallel
// or at once where one thread visits them in order (no atomics either way; the same bits
// on every backend and thread count). The tangential
// history lives at the pairs; a new list takes it from the last list's pairs, a reorder or
// a checkpoint passes it through the id-keyed ContactHistory.
#include "solvers/dem/contact_history.hpp"
#include "solvers/dem/contact_kinematics.hpp"
#include "solvers/dem/linear_spring_dashpot.hpp"
#include "solvers/dem/pair_contacts.hpp"
#include "solvers/dem/plane_wall.hpp"
#include "solvers/dem/spheres.hpp"
#include "solvers/dem/upper_pairs.hpp"
#include "solvers/dem/wall_contacts.hpp"
#include "src/core/csr_rows.hpp"
#include "src/core/extrema.hpp"
#include "src/core/neighbor_list.hpp"
#include "src/core/neighbor_sweep.hpp"
#include "src/core/half_pairs.hpp"
#include "src/core/reorder.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace dvisph::dem {

template <int D>
struct DemOptions {
  Real safety = 1.0 / 25;  // DEM step as a fraction of the shortest binary contact time
  bool rotation = true;    // false: angular velocities stay as they are (torques ignored)
  int history_capacity = D == 3 ? 16 : 8;  // contacts per bead, walls included
  // Contacts are searched this far (a fraction of the largest diameter) beyond touching:
  // a contact acts from inside the kick interval before the beads touch. It bounds the
  // speed: a bead may move at most skin/2 per step (checked).
  Real skin = 0.05;
  // The Verlet list holds pairs this much farther apart still (a fraction of the largest
  // diameter): it is rebuilt when a bead has moved half of it since the last build. On
  // the bead-bed settle (7 921 beads, 28 029 steps, one thread) 0.05, 0.1, 0.2 and 0.3
  // took 74.6, 74.8, 77.8 and 82.1 s (996, 513 and, for 0.3, 168 builds): 0.1, the
  // fewer builds of the two fastest (a build costs more on a GPU).
  Real list_skin = 0.1;
  // A contact deeper than this fraction of the smaller radius means the step or the
  // stiffness is wrong (an error, checked): at 1 m/s a 2.7 mm bead with k_n = 1000 N/m
  // sinks 12 % of its radius into a wall.
  Real max_overlap = 0.5;
  // Axes along which the box wraps (bit k: axis k): a bead leaving through one face comes
  // back through the other, and contacts are taken at the nearest image.
  unsigned periodic_axes = 0;
};

struct Energy {
  Real kinetic = 0;    // translation and rotation
  Real potential = 0;  // gravity, -m g.x
  Real spring = 0;     // normal and tangential springs of the contacts
  Real total() const { return kinetic + potential + spring; }
};

template <int D, class Space>
class DemSolver {
 public:
  using memory_space = typename Space::memory_space;
  using Law = LinearSpringDashpot<D>;
  static constexpr int R = rot_dim<D>;

  // The box bounds the cell list: beads must stay inside it (checked).
  DemSolver(const Spheres<D, Space>& spheres, std::vector<PlaneWall<D>> walls, const Law& law,
            const Vec<D>& box_lo, const Vec<D>& box_hi, const Vec<D>& gravity,
            DemOptions<D> options = {})
      : spheres_(spheres),
        walls_(std::move(walls)),
        law_(law),
        options_(options),
        box_lo_(box_lo),
        box_hi_(box_hi),
        gravity_(gravity),
        pairs_(spheres.n, static_cast<int>(walls_.size()), in_order()),
        history_(spheres.n, options.history_capacity),
        kinematics_(spheres.n),
        x_listed_("dvisph::dem::x_listed", spheres.n),
        old_offsets_("dvisph::dem::old_offsets", spheres.n + 1),
        status_("dvisph::dem::status") {
    const int n = spheres_.n;
    if (n < 1) throw std::invalid_argument("DemSolver: no spheres");
    const Real r_max = max_of<Space>(spheres_.radius, n, "dvisph::dem::largest_radius");
    const Real m_min = min_of<Space>(spheres_.mass, n, "dvisph::dem::smallest_mass");
    if (!(r_max > 0 && m_min > 0))
      throw std::invalid_argument("DemSolver: radius and mass must be > 0");
    skin_ = options_.skin * 2 * r_max;
    search_radius_ = 2 * r_max + skin_;
    list_skin_ = options_.list_skin * 2 * r_max;
    cells_ = CellList<D, Space>(Grid<D>(box_lo, box_hi, search_radius_ + list_skin_, options_.periodic_axes));
    walls_d_ = Kokkos::View<PlaneWall<D>*, memory_space>(
        Kokkos::view_alloc(Kokkos::WithoutInitializing, "dvisph::dem::walls"), walls_.size());
    upload_walls();
    build_list();
    load_history();
    // the lightest pair collides fastest
    dt_ = options_.safety * law_.contact_time(0.5 * m_min);
  }

  Spheres<D, Space>& spheres() { return spheres_; }
  const Spheres<D, Space>& spheres() const { return spheres_; }
  const std::vector<PlaneWall<D>>& walls() const { return walls_; }
  const Law& law() const { return law_; }
  Real time() const { return time_; }
  Real time_step() const { return dt_; }  // safety * contact time
  long list_builds() const { return list_builds_; }  // Verlet list builds so far
  const Vec<D>& box_lo() const { return box_lo_; }
  const Vec<D>& box_hi() const { return box_hi_; }
  // The fastest bead's speed now [m/s].
  Real max_speed() const {
    const auto v = spheres_.v;
    Real fastest = 0;
    Kokkos::parallel_reduce(
        "dvisph::dem::max_speed", Kokkos::RangePolicy<Space>(0, spheres_.n),
        KOKKOS_LAMBDA(int i, Real& m) {
          Real v2 = 0;
          for (int k = 0; k < D; ++k) v2 += v(i, k) * v(i, k);
          m = math::max(m, v2);
        },
        Kokkos::Max<Real>(fastest));
    return std::sqrt(fastest);
  }
  // Seconds spent in each stage of the steps so far (each fenced), in step order.
  static constexpr const char* stage_names[] = {"kick_drift", "contact_list", "pair_contacts",
                                                "gather_and_kick"};
  const std::array<double, 4>& stage_seconds() const { return stage_seconds_; }

  void set_wall_active(int w, bool active) {
    walls_.at(w).active = active;
    upload_walls();
  }

  // Advances by a fluid step in DEM sub-steps of at most time_step(), f_ext held.
  void advance(Real dt_fluid) {
    const int sub = std::max(1, static_cast<int>(std::ceil(dt_fluid / dt_ - 1e-9)));
    for (int s = 0; s < sub; ++s) step_unchecked(dt_fluid / sub);
    check();
  }
  void step(Real dt) {
    step_unchecked(dt);
    check();
  }

  // Sorts the beads by cell for memory locality; the history follows by id.
  void reorder() { permute(cells_.permutation()); }
  // Bead perm(a) becomes bead a, every per-bead field in place (views stay valid).
  template <class Perm>
  void permute(const Perm& perm) {
    store_history();  // by the ids of the current order
    spheres_.for_each_field([&](const char*, auto& field) {
      using V = std::decay_t<decltype(field)>;
      const V tmp(Kokkos::view_alloc(Kokkos::WithoutInitializing, field.label()), field.layout());
      gather_rows<Space>(tmp, field, perm);
      Kokkos::deep_copy(field, tmp);
    });
    history_.permute(perm);
    build_list();
    load_history();
  }

  // The whole state (beads in their current order, contact history, open gates, clock,
  // the forces velocity Verlet carries into the next step): restoring it continues a
  // run bit-identically. (A bed loaded into another scene takes the beads alone:
  // read_spheres.)
  void save(Checkpoint& c) const {
    auto s = spheres_;
    s.for_each_field([&](const char* name, const auto& field) { c.put(std::string("dem/") + name, field); });
    store_history();
    history_.save(c, "dem/history/");
    for (std::size_t w = 0; w < walls_.size(); ++w)
      c.set(fmt::format("dem/wall_{}_active", w), walls_[w].active);
    c.put("dem/x_listed", x_listed_);
    c.set("dem/t", time_);
    c.set("dem/forces_ready", forces_ready_);
  }
  void restore(const Checkpoint& c) {
    spheres_.for_each_field([&](const char* name, auto& field) { c.get(std::string("dem/") + name, field); });
    history_.restore(c, "dem/history/");
    for (std::size_t w = 0; w < walls_.size(); ++w)
      walls_[w].active = c.number(fmt::format("dem/wall_{}_active", w)) != 0;
    upload_walls();
    time_ = c.number("dem/t");
    forces_ready_ = c.number("dem/forces_ready") != 0;
    if (c.has("dem/x_listed")) {
      // the list as the run had it: built from the positions of its last build (same
      // pairs, same order), then swept at the current ones
      const decltype(x_listed_) now("dvisph::dem::x_now", spheres_.n);
      Kokkos::deep_copy(now, spheres_.x);
      c.get("dem/x_listed", spheres_.x);
      build_list();
      Kokkos::deep_copy(spheres_.x, now);
    } else {
      build_list();
    }
    load_history();
  }

  // Mean number of contacts per bead (walls included) at the last force evaluation.
  Real contacts_per_bead() const {
    const auto pairs = pairs_;
    const auto list = half_.rows();
    const int nw = static_cast<int>(walls_.size());
    long total = 0;
    Kokkos::parallel_reduce(
        "dvisph::dem::count_contacts", Kokkos::RangePolicy<Space>(0, spheres_.n),
        KOKKOS_LAMBDA(int i, long& s) {
          for (int a = list.upper_offsets(i); a < list.upper_offsets(i + 1); ++a) s += 2 * pairs.touching(a);
          for (int w = 0; w < nw; ++w) s += pairs.wall_touching(i, w);
        },
        total);
    return static_cast<Real>(total) / spheres_.n;
  }

  // Kinetic, gravitational and spring energy now (for diagnostics; f_ext's work is not
  // tracked).
  Energy energy() const {
    const auto x = spheres_.x, v = spheres_.v;
    const auto om = spheres_.omega;  // rotational: [rdim] columns
    const auto rad = spheres_.radius, m = spheres_.mass, I = spheres_.inertia;
    const Vec<D> g = gravity_;
    const Law law = law_;
    const auto walls = walls_d_;
    const int nw = static_cast<int>(walls_.size());
    const auto sweep = list_.sweep(search_radius_);
    const auto pairs = pairs_;
    const auto list = half_.rows();
    const auto policy = Kokkos::RangePolicy<Space>(0, spheres_.n);
    Energy e;
    Kokkos::parallel_reduce(
        "dvisph::dem::energy::kinetic", policy,
        KOKKOS_LAMBDA(int i, Real& s) {
          for (int k = 0; k < D; ++k) s += 0.5 * m(i) * v(i, k) * v(i, k);
          for (int c = 0; c < R; ++c) s += 0.5 * I(i) * om(i, c) * om(i, c);
        },
        e.kinetic);
    Kokkos::parallel_reduce(
        "dvisph::dem::energy::potential", policy,
        KOKKOS_LAMBDA(int i, Real& s) { s -= m(i) * dot(g, row<D>(x, i)); }, e.potential);
    Kokkos::parallel_reduce(
        "dvisph::dem::energy::spring", policy,
        KOKKOS_LAMBDA(int i, Real& s) {
          const Vec<D> xi = row<D>(x, i);
          const Vec<D> zero = Vec<D>::zero();
          // a pair's energy is shared by its two beads
          sweep.for_each(i, xi, [&](int j, const Vec<D>&, Real r) {
            if (j != i) s += 0.5 * law.energy(rad(i) + rad(j) - r, zero);
          });
          for (int w = 0; w < nw; ++w)
            if (walls(w).active) s += law.energy(rad(i) - walls(w).distance(xi), zero);
          for (int a = list.upper_offsets(i); a < list.upper_offsets(i + 1); ++a)
            s += law.energy(0, row<D>(pairs.xi, a));
          for (int w = 0; w < nw; ++w) s += law.energy(0, pairs.wall(i, w));
        },
        e.spring);
    return e;
  }

  // The stages of a step (public only because CUDA takes device lambdas in public
  // member functions alone).

  // v += dt/2 a, x += dt v; and the predicted velocity over the next drift, v + dt a,
  // that the contact law needs to place each contact's start and end in the step, all
  // written to the contact kinematics too. dt = 0 packs the state as it is. Returns
  // whether some bead has now moved more than half the list skin since the list was built.
  bool kick_drift(Real dt) {
    const auto x = spheres_.x, v = spheres_.v;
    const auto om = spheres_.omega;  // rotational: [rdim] columns
    const auto f = spheres_.force, fext = spheres_.f_ext;
    const auto t = spheres_.torque;  // rotational: [rdim] columns
    const auto m = spheres_.mass, I = spheres_.inertia, rad = spheres_.radius;
    const auto kin = kinematics_.row;
    using K = ContactKinematics<D, Space>;
    const auto status = status_;
    const Vec<D> g = gravity_, lo = box_lo_, hi = box_hi_;
    const Periodic<D> periodic = cells_.grid().periodic;
    const bool rotation = options_.rotation;
    const Real max_move2 = 0.25 * skin_ * skin_;
    const auto x0 = x_listed_;
    Real moved2 = 0;
    Kokkos::parallel_reduce(
        "dvisph::dem::kick_drift", Kokkos::RangePolicy<Space>(0, spheres_.n),
        KOKKOS_LAMBDA(int i, Real& most) {
          // two divisions a bead, not six; the new state is computed before it is
          // stored (a store to a double may alias dt, so dt is read once into h)
          const Real h = dt, inv_m = 1 / m(i), inv_I = 1 / I(i);
          Vec<D> xn, vn, moved;
          Real move2 = 0;
          bool outside = false;
          for (int k = 0; k < D; ++k) {
            const Real a = (f(i, k) + fext(i, k)) * inv_m + g[k];
            vn[k] = v(i, k) + 0.5 * h * a;
            xn[k] = periodic.wrap(x(i, k) + h * vn[k], k);
            kin(i, K::va0 + k) = vn[k] + h * a;
            move2 += h * h * vn[k] * vn[k];
            outside = outside || !(xn[k] >= lo[k] && xn[k] <= hi[k]);
            moved[k] = xn[k] - x0(i, k);
          }
          for (int k = 0; k < D; ++k) {
            x(i, k) = xn[k], v(i, k) = vn[k];
            kin(i, K::x0 + k) = xn[k], kin(i, K::v0 + k) = vn[k];
          }
          for (int c = 0; c < R; ++c) {
            const Real alpha = rotation ? t(i, c) * inv_I : 0;
            const Real w = om(i, c) + 0.5 * h * alpha;
            om(i, c) = w;
            kin(i, K::w0 + c) = w;
            kin(i, K::wa0 + c) = w + h * alpha;
          }
          kin(i, K::r0) = rad(i);
          if (outside) Kokkos::atomic_fetch_max(&status(outside_bead), i + 1);
          if (move2 > max_move2) Kokkos::atomic_fetch_max(&status(fast_bead), i + 1);
          periodic.nearest_image(moved);
          const Real d2 = dot(moved, moved);
          if (d2 > most) most = d2;
        },
        Kokkos::Max<Real>(moved2));
    return 4 * moved2 > list_skin_ * list_skin_;
  }

  // Contact force and torque on each bead at the current positions, with the half-step
  // velocities and the predicted ones in the contact kinematics (kick_drift); kick: then
  // v += dt/2 a with the forces just summed (the closing half kick, fused). Each bead
  // pair is evaluated once, by its lower index (solvers/dem/upper_pairs.hpp), which adds
  // its side and hands the exact opposite to the other bead; on one thread the beads
  // are visited in order and the other bead's side is added to its sums at once,
  // otherwise it is left at the pair for the other bead to gather in a second kernel.
  // A bead's force is the sum over its lower partners (ascending) plus that over its
  // upper ones plus its walls': the same bits either way.
  void contact_forces(Real dt, bool kick) {
    if (pairs_.in_order) {
      timed(2, [&] { contacts_in_order(dt, kick); });
    } else {
      timed(2, [&] { pair_contacts(dt); });
      timed(3, [&] { gather_contacts(dt, kick); });
    }
  }

  void pair_contacts(Real dt) {
    const auto f = spheres_.force;
    const auto t = spheres_.torque;  // rotational: [rdim] columns
    const auto pairs = pairs_;
    const UpperPairs<D, Space> upper = upper_pairs(dt);
    const PartnerRecord<D, Space> partner{pairs_.record, half_.rows().mirror};
    Kokkos::parallel_for(
        "dvisph::dem::pair_contacts", Kokkos::RangePolicy<Space>(0, spheres_.n), KOKKOS_LAMBDA(int i) {
          Vec<D> fi = Vec<D>::zero();
          Rot<D> ti = Rot<D>::zero();
          pairs.upper_touching(i) = upper(i, fi, ti, partner);
          for (int k = 0; k < D; ++k) f(i, k) = fi[k];
          for (int c = 0; c < R; ++c) t(i, c) = ti[c];
        });
  }

  void gather_contacts(Real dt, bool kick) {
    const auto f = spheres_.force;
    const auto t = spheres_.torque;  // rotational: [rdim] columns
    const auto list = half_.rows();
    const auto pairs = pairs_;
    const WallContacts<D, Space> walls = wall_contacts(dt);
    const Closing closing = closing_kick(dt, kick);
    using P = PairContacts<D, Space>;
    Kokkos::parallel_for(
        "dvisph::dem::gather_contacts", Kokkos::RangePolicy<Space>(0, spheres_.n), KOKKOS_LAMBDA(int i) {
          // the pairs that partners j < i evaluated (a pair that does not touch holds zeros)
          Vec<D> fi = Vec<D>::zero();
          Rot<D> ti = Rot<D>::zero();
          int count = pairs.upper_touching(i);
          for (int b = list.lower_offsets(i); b < list.lower_offsets(i + 1); ++b) {
            fi += columns<D>(pairs.record, b, P::force);
            ti += columns<R>(pairs.record, b, P::torque);
            count += pairs.record(b, P::touches) != 0;
          }
          fi += row<D>(f, i);
          ti += row<R>(t, i);
          count += walls(i, fi, ti);
          closing(i, fi, ti, count);
        });
  }

  // One thread: both sides of each pair in one pass (no gather), on Kokkos::Serial,
  // which visits the beads in index order.
  void contacts_in_order(Real dt, bool kick) {
#ifdef KOKKOS_ENABLE_SERIAL
    const auto pairs = pairs_;
    const UpperPairs<D, Space> upper = upper_pairs(dt);
    const PartnerSums<D, Space> partner{pairs_.partner_sums};
    const WallContacts<D, Space> walls = wall_contacts(dt);
    const Closing closing = closing_kick(dt, kick);
    using P = PairContacts<D, Space>;
    Kokkos::parallel_for(
        "dvisph::dem::contacts_in_order", Kokkos::RangePolicy<Kokkos::Serial>(0, spheres_.n),
        KOKKOS_LAMBDA(int i) {
          Vec<D> fu = Vec<D>::zero();
          Rot<D> tu = Rot<D>::zero();
          int count = upper(i, fu, tu, partner);
          // the partners j < i have added their sides (their turns came first)
          Vec<D> fi = columns<D>(pairs.partner_sums, i, P::force) + fu;
          Rot<D> ti = columns<R>(pairs.partner_sums, i, P::torque) + tu;
          count += static_cast<int>(pairs.partner_sums(i, P::touches));
          for (int q = 0; q < P::width; ++q) pairs.partner_sums(i, q) = 0;
          count += walls(i, fi, ti);
          closing(i, fi, ti, count);
        });
#else
    (void)dt, (void)kick;
    throw std::logic_error("DemSolver: in-order contacts need Kokkos::Serial");
#endif
  }

  // The contacts' history from the listed pairs into the id-keyed table (before a new
  // list, a reorder or a checkpoint): each bead's upper pairs, lower pairs, walls.
  void store_history() const {
    const auto id = spheres_.id;
    const auto list = half_.rows();
    const auto pairs = pairs_;
    const auto out = history_.writer();
    const int nw = static_cast<int>(walls_.size());
    Kokkos::parallel_for(
        "dvisph::dem::store_history", Kokkos::RangePolicy<Space>(0, spheres_.n), KOKKOS_LAMBDA(int i) {
          int count = 0;
          for (int a = list.upper_offsets(i); a < list.upper_offsets(i + 1); ++a)
            if (pairs.touching(a)) out.add(i, count, id(list.upper(a)), row<D>(pairs.xi, a));
          for (int b = list.lower_offsets(i); b < list.lower_offsets(i + 1); ++b) {
            const int e = list.lower_entry(b);
            if (pairs.touching(e)) out.add(i, count, id(list.lower(b)), (-1.0) * row<D>(pairs.xi, e));
          }
          for (int w = 0; w < nw; ++w)
            if (pairs.wall_touching(i, w)) out.add(i, count, -(w + 1), pairs.wall(i, w));
          out.close(i, count);
        });
  }
  // The table's history onto the listed pairs (after a new list is built, a reorder or a
  // restart), and the walls near each bead.
  void load_history() {
    attach_history("dvisph::dem::load_history", FromTable{history_.table(), spheres_.id});
  }
  // A new list at the current positions, each listed pair taking its state from the same
  // pair of the last list: the beads keep their indices between builds, so pair (i, j)
  // is in i's old upper row, and the walls keep theirs per bead. No pass through the
  // id-keyed table (store_history and load_history took 0.3 of a build on the bead-bed
  // settle).
  void rebuild_list() {
    const auto rows = half_.rows();
    const int n = spheres_.n, listed = half_.pairs();
    reserve_entries(old_upper_, listed, "dvisph::dem::old_upper");
    reserve_entries(old_touching_, listed, "dvisph::dem::old_touching");
    reserve_entries(old_xi_, listed, "dvisph::dem::old_xi");
    using range = std::pair<int, int>;
    Kokkos::deep_copy(old_offsets_, Kokkos::subview(rows.upper_offsets, range(0, n + 1)));
    Kokkos::deep_copy(Kokkos::subview(old_upper_, range(0, listed)), Kokkos::subview(rows.upper, range(0, listed)));
    Kokkos::deep_copy(Kokkos::subview(old_touching_, range(0, listed)),
                      Kokkos::subview(pairs_.touching, range(0, listed)));
    Kokkos::deep_copy(Kokkos::subview(old_xi_, range(0, listed), Kokkos::ALL),
                      Kokkos::subview(pairs_.xi, range(0, listed), Kokkos::ALL));
    build_list();
    attach_history("dvisph::dem::carry_history", FromOldList{old_offsets_, old_upper_, old_touching_, old_xi_, pairs_});
  }

  // Where attach_history takes the pairs' and walls' state from: the id-keyed table, or
  // the last list (class scope: types that kernels capture)
  struct FromTable {
    typename ContactHistory<D, Space>::Table table;
    Kokkos::View<const int*, memory_space> id;
    KOKKOS_INLINE_FUNCTION bool pair(int i, int j, Vec<D>& xi) const { return take(i, id(j), xi); }
    KOKKOS_INLINE_FUNCTION bool wall(int i, int w, Vec<D>& xi) const { return take(i, -(w + 1), xi); }
    KOKKOS_INLINE_FUNCTION bool take(int i, int partner, Vec<D>& xi) const {
      const int s = table.find(i, partner);
      for (int k = 0; k < D; ++k) xi[k] = s >= 0 ? table.xi(i, s, k) : 0;
      return s >= 0;
    }
  };
  struct FromOldList {
    Kokkos::View<const int*, memory_space> offsets, upper;
    Kokkos::View<const char*, memory_space> touching;
    Kokkos::View<const Real* [D], memory_space> xi_old;
    PairContacts<D, Space> pairs;
    KOKKOS_INLINE_FUNCTION bool pair(int i, int j, Vec<D>& xi) const {
      int s = -1;
      for (int o = offsets(i); o < offsets(i + 1) && s < 0; ++o)
        if (upper(o) == j) s = o;
      for (int k = 0; k < D; ++k) xi[k] = s >= 0 ? xi_old(s, k) : 0;
      return s >= 0 && touching(s);
    }
    KOKKOS_INLINE_FUNCTION bool wall(int i, int w, Vec<D>& xi) const {
      xi = pairs.wall(i, w);
      return pairs.wall_touching(i, w);
    }
  };
  // Each listed pair's and each wall's touching flag and tangential displacement from
  // `from` (pair(i, j, xi), wall(i, w, xi): whether it touches), and the walls near each
  // bead: a bead moves at most half the list skin from where the list was built (and
  // where it is now), so a wall farther than skin + list skin now stays beyond the search
  // skin until the next build.
  template <class From>
  void attach_history(const char* label, const From& from) {
    const auto x = spheres_.x;
    const auto rad = spheres_.radius;
    const auto list = half_.rows();
    const auto pairs = pairs_;
    const auto walls = walls_d_;
    const int nw = static_cast<int>(walls_.size());
    const Real reach = skin_ + list_skin_;
    Kokkos::parallel_for(label, Kokkos::RangePolicy<Space>(0, spheres_.n), KOKKOS_LAMBDA(int i) {
      Vec<D> xi;
      for (int a = list.upper_offsets(i); a < list.upper_offsets(i + 1); ++a) {
        pairs.touching(a) = from.pair(i, list.upper(a), xi);
        set_columns<D>(pairs.xi, a, 0, xi);
        if (!pairs.in_order)
          for (int q = 0; q < PairContacts<D, Space>::width; ++q) pairs.record(list.mirror(a), q) = 0;
      }
      unsigned near = 0;
      for (int w = 0; w < nw; ++w) {
        const bool touching = from.wall(i, w, xi);
        pairs.wall_touching(i, w) = touching;
        pairs.set_wall(i, w, xi);
        if (touching || walls(w).distance(row<D>(x, i)) - rad(i) <= reach) near |= 1u << w;
      }
      pairs.near_walls(i) = near;
    });
  }

 private:
  void build_list() {
    cells_.build(spheres_.x, spheres_.n);
    list_.build(CellSweep<D, Space>(cells_, spheres_.x, search_radius_ + list_skin_), spheres_.x,
                spheres_.n);
    half_.build(list_.sweep(), spheres_.n);
    pairs_.reserve(half_.pairs());
    pairs_.set_masses(half_.rows(), spheres_.mass, spheres_.n);
    Kokkos::deep_copy(x_listed_, spheres_.x);
    ++list_builds_;
  }

  void step_unchecked(Real dt) {
    bool changed = false;
    for (auto& w : walls_)
      if (w.active && time_ + 0.5 * dt > w.remove_at) {  // a gate opens
        w.active = false;
        changed = true;
      }
    if (changed) upload_walls();
    if (!forces_ready_) {
      // forces at the start, from the velocities now; the history is not advanced (the
      // pairs take it back from the table)
      store_history();
      kick_drift(0);
      contact_forces(dt, false);
      load_history();
      forces_ready_ = true;
    }
    bool list_due = false;
    timed(0, [&] { list_due = kick_drift(dt); });
    timed(1, [&] {
      if (list_due) rebuild_list();
    });
    contact_forces(dt, true);
    time_ += dt;
  }

  UpperPairs<D, Space> upper_pairs(Real dt) const {
    return {kinematics_, half_.rows(), pairs_, law_, cells_.grid().periodic, status_, deep_bead,
            search_radius_ * search_radius_, options_.max_overlap, dt};
  }
  WallContacts<D, Space> wall_contacts(Real dt) const {
    return {kinematics_, pairs_, walls_d_, spheres_.mass, law_, status_, static_cast<int>(walls_.size()),
            deep_bead, skin_, options_.max_overlap, dt};
  }
  // A bead's contact force and torque stored, the closing half kick v += dt/2 a when
  // `kick`, and the count of its contacts checked against the history's room.
  struct Closing {
    Kokkos::View<Real* [D], memory_space> f, v, fext;
    Kokkos::View<Real* [R], memory_space> t, om;
    Kokkos::View<const Real*, memory_space> m, I;
    Kokkos::View<int*, memory_space> status;
    Vec<D> g;
    Real dt;
    int capacity;
    bool kick, rotation;
    KOKKOS_INLINE_FUNCTION void operator()(int i, const Vec<D>& fi, const Rot<D>& ti, int count) const {
      for (int k = 0; k < D; ++k) f(i, k) = fi[k];
      for (int c = 0; c < R; ++c) t(i, c) = ti[c];
      if (kick) {
        const Real half = 0.5 * dt, inv_m = 1 / m(i);
        for (int k = 0; k < D; ++k) v(i, k) += half * ((fi[k] + fext(i, k)) * inv_m + g[k]);
        if (rotation) {
          const Real inv_I = 1 / I(i);
          for (int c = 0; c < R; ++c) om(i, c) += half * ti[c] * inv_I;
        }
      }
      if (count > capacity) Kokkos::atomic_fetch_max(&status(crowded_bead), i + 1);
    }
  };
  Closing closing_kick(Real dt, bool kick) const {
    return {spheres_.force, spheres_.v, spheres_.f_ext, spheres_.torque, spheres_.omega, spheres_.mass,
            spheres_.inertia, status_, gravity_, dt, history_.capacity(), kick, options_.rotation};
  }

  template <class F>
  void timed(int stage, F&& f) {
    Kokkos::Profiling::pushRegion(std::string("dvisph::dem::") + stage_names[stage]);
    Kokkos::Timer timer;
    f();
    Space().fence();
    stage_seconds_[stage] += timer.seconds();
    Kokkos::Profiling::popRegion();
  }

  // One thread on the host: the beads can be visited in order (contacts_in_order).
  static bool in_order() {
#ifdef KOKKOS_ENABLE_SERIAL
    return Kokkos::SpaceAccessibility<Kokkos::HostSpace, memory_space>::accessible && Space().concurrency() == 1;
#else
    return false;
#endif
  }

  void upload_walls() {
    Kokkos::View<PlaneWall<D>*, Kokkos::HostSpace, Kokkos::MemoryUnmanaged> h(walls_.data(),
                                                                              walls_.size());
    Kokkos::deep_copy(walls_d_, h);
  }

  // Flags set by the kernels: 1 + the highest index of a bead that did it, 0 none.
  enum Flag { outside_bead, fast_bead, deep_bead, crowded_bead, flags };

  void check() const {
    const auto status = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), status_);
    if (const int lost = history_.overflows())
      throw std::runtime_error("DemSolver: " + std::to_string(lost) +
                               " contacts found no room in the contact history (capacity " +
                               std::to_string(history_.capacity()) +
                               " per bead): raise DemOptions::history_capacity");
    const char* what[flags] = {
        "left the box",
        "moved more than half the contact search skin in one step (contacts may be missed; "
        "lower the DEM step)",
        "overlaps a bead or wall by more than DemOptions::max_overlap of its radius (the DEM "
        "step is too long or the stiffness too low for the speed)",
        "touches more beads and walls than the contact history holds "
        "(DemOptions::history_capacity; raise it)"};
    for (int f = 0; f < flags; ++f) {
      if (status(f) == 0) continue;
      const int i = status(f) - 1;
      const auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                         Kokkos::subview(spheres_.x, i, Kokkos::ALL));
      const auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                         Kokkos::subview(spheres_.v, i, Kokkos::ALL));
      const auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                                          Kokkos::subview(spheres_.id, i));
      std::string pos, vel;
      for (int k = 0; k < D; ++k)
        pos += fmt::format("{}{:.6g}", k ? ", " : "", x(k)), vel += fmt::format("{}{:.4g}", k ? ", " : "", v(k));
      throw std::runtime_error(fmt::format("bead {} at ({}) m, velocity ({}) m/s, {}", id(), pos,
                                           vel, what[f]));
    }
  }

  Spheres<D, Space> spheres_;
  std::vector<PlaneWall<D>> walls_;
  Kokkos::View<PlaneWall<D>*, memory_space> walls_d_;
  Law law_;
  DemOptions<D> options_;
  Vec<D> box_lo_, box_hi_, gravity_;
  CellList<D, Space> cells_;
  NeighborList<D, Space> list_;
  HalfPairs<Space> half_;
  PairContacts<D, Space> pairs_;
  ContactHistory<D, Space> history_;
  ContactKinematics<D, Space> kinematics_;
  Kokkos::View<Real* [D], memory_space> x_listed_;  // positions at the last list build
  // the last list's upper rows and their pairs' state, while rebuild_list carries them over
  Kokkos::View<int*, memory_space> old_offsets_, old_upper_;
  Kokkos::View<char*, memory_space> old_touching_;
  Kokkos::View<Real* [D], memory_space> old_xi_;
  Kokkos::View<int[flags], memory_space> status_;
  Real skin_ = 0, search_radius_ = 0, list_skin_ = 0, dt_ = 0, time_ = 0;
  long list_builds_ = 0;
  std::array<double, 4> stage_seconds_ = {};
  bool forces_ready_ = false;
};

}  // namespace dvisph::dem
