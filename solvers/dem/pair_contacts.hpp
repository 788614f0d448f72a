#pragma once
// The state of the contacts between steps, kept where the kernels use it: at each listed
// bead pair (i, j), i < j (src/core/half_pairs.hpp), and at each bead-wall pair. Per
// pair: whether the two touch now, i's tangential displacement xi (0 when they do not
// touch; j's is the opposite), and, where bead j gathers its side in a second kernel
// (solvers/dem/upper_pairs.hpp), a `record` at the pair's lower entry of j (HalfPairs'
// mirror): the force and torque on j and a copy of the touching flag, so j reads its
// rows in order and counts its contacts from them; and per bead, how many of its upper
// pairs touch. The two copies save the gather a pass over the flags. A kernel that
// visits the beads in order adds j's side to j's `partner_sums` instead. The pair
// kernel reads and rewrites xi in place, so no search by partner is made in a step;
// the id-keyed ContactHistory is the form kept across list builds, reorders and
// checkpoints.
#include "solvers/dem/rotation.hpp"

#include <stdexcept>
#include <string>

namespace dvisph::dem {

template <int D, class Space>
struct PairContacts {
  using memory_space = typename Space::memory_space;
  static constexpr int R = rot_dim<D>;
  // columns of `record` and `partner_sums`: the force and torque on j, 1 while the pair
  // touches (so that j counts its contacts from the rows it reads anyway)
  static constexpr int force = 0, torque = D, touches = D + R, width = D + R + 1;

  Kokkos::View<Real* [width], memory_space> record;        // per pair (gathered), or
  Kokkos::View<Real* [width], memory_space> partner_sums;  // per bead (in-order kernel)
  Kokkos::View<Real*, memory_space> sqrt_m;  // of the pair's reduced mass, set at the list build
  Kokkos::View<Real* [D], memory_space> xi;
  Kokkos::View<char*, memory_space> touching;
  Kokkos::View<int*, memory_space> upper_touching;  // per bead i: its pairs (i, j > i) that touch
  // walls: bead i, wall w; wall_xi holds wall w's displacement in columns w D .. w D + D - 1
  Kokkos::View<Real**, memory_space> wall_xi;
  Kokkos::View<char**, memory_space> wall_touching;
  // bit w: wall w is near bead i, so that until the next list build it may touch it; the
  // other walls are not looked at (most beads are far from all walls)
  Kokkos::View<unsigned*, memory_space> near_walls;
  static constexpr int max_walls = 32;

  bool in_order = false;  // partner_sums, not record: DemSolver::contacts_in_order

  PairContacts() = default;
  PairContacts(int beads, int walls, bool beads_in_order)
      : partner_sums("dvisph::dem::partner_sums", beads_in_order ? beads : 0),
        upper_touching("dvisph::dem::upper_touching", beads),
        wall_xi("dvisph::dem::wall_xi", beads, walls * D),
        wall_touching("dvisph::dem::wall_touching", beads, walls),
        near_walls("dvisph::dem::near_walls", beads),
        in_order(beads_in_order) {
    if (walls > max_walls) throw std::invalid_argument("PairContacts: more than 32 walls");
  }

  // Room for `entries` pairs (kept when there is enough; the contents are refilled).
  void reserve(int entries) {
    if (static_cast<int>(touching.extent(0)) >= entries) return;
    const int size = entries + entries / 8;
    const auto none = Kokkos::view_alloc(Kokkos::WithoutInitializing, std::string("dvisph::dem::pairs"));
    if (!in_order) record = decltype(record)(none, size);
    xi = decltype(xi)(none, size);
    touching = decltype(touching)(none, size);
    sqrt_m = decltype(sqrt_m)(none, size);
  }

  // sqrt_m of the listed pairs (Rows: HalfPairs::Rows), once per list build: the same
  // bits as at every pair evaluation, without its division and square root.
  template <class Rows, class Masses>
  void set_masses(const Rows& list, const Masses& m, int n) const {
    const auto root = sqrt_m;
    Kokkos::parallel_for(
        "dvisph::dem::pair_masses", Kokkos::RangePolicy<typename Space::execution_space>(0, n),
        KOKKOS_LAMBDA(int i) {
          for (int a = list.upper_offsets(i); a < list.upper_offsets(i + 1); ++a) {
            const int j = list.upper(a);
            root(a) = math::sqrt(m(i) * m(j) / (m(i) + m(j)));
          }
        });
  }

  KOKKOS_INLINE_FUNCTION Vec<D> wall(int i, int w) const { return columns<D>(wall_xi, i, w * D); }
  KOKKOS_INLINE_FUNCTION void set_wall(int i, int w, const Vec<D>& x) const { set_columns<D>(wall_xi, i, w * D, x); }
};

}  // namespace dvisph::dem
