#pragma once
// The contacts of a bead i with its listed partners j > i (HalfPairs' upper row), each
// pair evaluated once, here: the force and torque on i are added to i's sums, the
// pair's touching flag and tangential history are updated in place, and the partner's
// side (the exact opposite force, its own torque) is handed to a `Partner`:
// - PartnerRecord writes it at the pair's lower entry, for j to gather in a second
//   kernel (any order of evaluation: every backend and thread count);
// - PartnerSums adds it to j's running sums, for a kernel that visits the beads in index
//   order, so that j's sums are complete when its turn comes (one thread: no gather pass).
// Both give j the same sum in the same order (j's lower partners in ascending index),
// so the two kernels give the same bits.
#include "solvers/dem/contact_kinematics.hpp"
#include "solvers/dem/linear_spring_dashpot.hpp"
#include "solvers/dem/pair_contacts.hpp"
#include "src/core/half_pairs.hpp"
#include "src/core/periodic.hpp"

namespace dvisph::dem {

template <int D, class Space>
struct PartnerRecord {
  using P = PairContacts<D, Space>;
  static constexpr int R = P::R;
  Kokkos::View<Real* [P::width], typename Space::memory_space> record;
  Kokkos::View<const int*, typename Space::memory_space> mirror;

  KOKKOS_INLINE_FUNCTION void add(int a, int, const Vec<D>& f, const Rot<D>& t) const {
    const int b = mirror(a);
    set_columns<D>(record, b, P::force, f);
    set_columns<R>(record, b, P::torque, t);
    record(b, P::touches) = 1;
  }
  // a contact that ends leaves no force (the gather adds every row)
  KOKKOS_INLINE_FUNCTION void end(int a) const {
    for (int q = 0; q < P::width; ++q) record(mirror(a), q) = 0;
  }
};

template <int D, class Space>
struct PartnerSums {
  using P = PairContacts<D, Space>;
  static constexpr int R = P::R;
  Kokkos::View<Real* [P::width], typename Space::memory_space> sums;  // per bead, zeroed once used

  KOKKOS_INLINE_FUNCTION void add(int, int j, const Vec<D>& f, const Rot<D>& t) const {
    for (int k = 0; k < D; ++k) sums(j, P::force + k) += f[k];
    for (int c = 0; c < R; ++c) sums(j, P::torque + c) += t[c];
    sums(j, P::touches) += 1;
  }
  KOKKOS_INLINE_FUNCTION void end(int) const {}
};

template <int D, class Space>
struct UpperPairs {
  using P = PairContacts<D, Space>;
  using K = ContactKinematics<D, Space>;
  using memory_space = typename Space::memory_space;
  static constexpr int R = rot_dim<D>;
  // pairs per chunk (below): 4 and 8 take the same time on the bead-bed settle (about
  // 4 listed pairs per bead); on a GPU a thread's arrays would live in slow local
  // memory and a warp diverges anyway, so there it takes one pair at a time
  static constexpr int chunk = Kokkos::SpaceAccessibility<Kokkos::HostSpace, memory_space>::accessible ? 4 : 1;

  K kin;
  typename HalfPairs<Space>::Rows list;
  P pairs;
  LinearSpringDashpot<D> law;
  Periodic<D> periodic;
  Kokkos::View<int*, memory_space> status;
  int deep_flag;
  Real radius2, max_overlap, dt;

  // Adds the contacts' force and torque on i to fi and ti; returns how many touch.
  template <class Partner>
  KOKKOS_INLINE_FUNCTION int operator()(int i, Vec<D>& fi, Rot<D>& ti, const Partner& partner) const {
    const Vec<D> xi = kin.x(i), vi = kin.v(i), vai = kin.v_ahead(i);
    const Rot<D> wi = kin.omega(i), wai = kin.omega_ahead(i);
    const Real ri = kin.radius(i);
    int contacts = 0;
    const int end = list.upper_offsets(i + 1);
    for (int begin = list.upper_offsets(i); begin < end; begin += chunk) {
      // A chunk of listed pairs in passes: their partners' rows gathered column by
      // column; the distances, and if no lane is within the search radius (beads
      // falling side by side, as in a settle's first steps) nothing more than the
      // contacts that end; else the geometry of every lane in one loop without a
      // branch, which the compiler runs in SIMD lanes (same operations, same bits, as
      // one by one); the contacts that start or end; the law on those that touch alone
      // (in a bed, near pairs touch or not at random, a branch that is mispredicted). A
      // lane past the chunk's end takes bead i itself: r = 0 makes NaNs that touch
      // nothing.
      const int lanes = math::min(chunk, end - begin);
      int j[chunk];
      for (int c = 0; c < chunk; ++c) j[c] = c < lanes ? list.upper(begin + c) : i;
      Real partner_row[K::width][chunk];  // x0 .. x0 + D - 1: the separation x_i - x_j
      for (int q = 0; q < K::width; ++q)
        for (int c = 0; c < chunk; ++c) partner_row[q][c] = kin.row(j[c], q);
      for (int k = 0; k < D; ++k) {
        Real* x = partner_row[K::x0 + k];
        for (int c = 0; c < chunk; ++c) x[c] = xi[k] - x[c];
        if (periodic.wraps(k))  // (per axis, not per lane: a branch keeps loops scalar)
          for (int c = 0; c < chunk; ++c) x[c] = periodic.nearest(x[c], k);
      }
      Real gap[4][chunk], normal[D][chunk], v_before[D][chunk], v_after[D][chunk];
      Real touch[chunk] = {};  // 1 or 0 (a bool array keeps GCC 12 from vectorizing)
      // (dist2 once: with the dot product repeated in the geometry, the pair stage of a
      // settled bed took 6 % longer)
      Real dist2[chunk];
      int near = 0;
      for (int c = 0; c < chunk; ++c) {
        dist2[c] = partner_row[K::x0][c] * partner_row[K::x0][c];
        for (int k = 1; k < D; ++k) dist2[c] += partner_row[K::x0 + k][c] * partner_row[K::x0 + k][c];
        near += (c < lanes) & (dist2[c] < radius2);
      }
      if (near > 0) {
        for (int c = 0; c < chunk; ++c) {
          Vec<D> xij, dv, dva;
          Rot<D> wj, waj;
          for (int k = 0; k < D; ++k) {
            xij[k] = partner_row[K::x0 + k][c];
            dv[k] = vi[k] - partner_row[K::v0 + k][c];
            dva[k] = vai[k] - partner_row[K::va0 + k][c];
          }
          for (int q = 0; q < R; ++q) wj[q] = partner_row[K::w0 + q][c], waj[q] = partner_row[K::wa0 + q][c];
          const Real r2 = dist2[c], r = math::sqrt(r2), rj = partner_row[K::r0][c];
          // dv: i's centre relative to j's (before, after t); spin = r_i w_i + r_j w_j,
          // so the contact points move apart at dv - spin x nrm.
          const Vec<D> nrm = (1 / r) * xij;
          const Overlaps d = Overlaps::along(ri + rj - r, dot(dv, nrm), dot(dva, nrm), dt);
          const Vec<D> vb = dv - cross(ri * wi + rj * wj, nrm), va = dva - cross(ri * wai + rj * waj, nrm);
          gap[0][c] = d.prev, gap[1][c] = d.lo, gap[2][c] = d.now, gap[3][c] = d.hi;
          for (int k = 0; k < D; ++k) normal[k][c] = nrm[k], v_before[k][c] = vb[k], v_after[k][c] = va[k];
          touch[c] = ((r2 < radius2) & d.touching()) ? 1 : 0;
        }
      }
      int entry[chunk], touching = 0;
      for (int c = 0; c < lanes; ++c) {
        const int a = begin + c;
        entry[touching] = c;
        const bool now = touch[c] != 0;
        touching += now;
        if (now != static_cast<bool>(pairs.touching(a))) {
          pairs.touching(a) = now;
          if (!now) {  // a contact that ends leaves no history
            for (int k = 0; k < D; ++k) pairs.xi(a, k) = 0;
            partner.end(a);
          }
        }
      }
      for (int e = 0; e < touching; ++e) {
        const int c = entry[e], a = begin + c;
        const Real rj = partner_row[K::r0][c];
        Contact<D> ct{{gap[0][c], gap[1][c], gap[2][c], gap[3][c]}, {}, {}, {}, pairs.sqrt_m(a)};
        for (int k = 0; k < D; ++k)
          ct.normal[k] = normal[k][c], ct.v_before[k] = v_before[k][c], ct.v_after[k] = v_after[k][c];
        if (ct.overlap.now > max_overlap * math::min(ri, rj)) Kokkos::atomic_fetch_max(&status(deep_flag), i + 1);
        // xi(a) is the history of a contact that touched at the last step, else 0
        const ContactResponse<D> res = law(ct, row<D>(pairs.xi, a), dt);
        // the torque on either bead is minus its radius times n x F (n from j to i)
        const Rot<D> moment = cross(ct.normal, res.force);
        fi += res.force;
        ti += (-ri) * moment;
        partner.add(a, j[c], (-1.0) * res.force, (-rj) * moment);
        set_columns<D>(pairs.xi, a, 0, res.xi);
      }
      contacts += touching;
    }
    return contacts;
  }
};

}  // namespace dvisph::dem
