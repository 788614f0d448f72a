#pragma once
// The front of a dam break or a collapse (src/fluid_output.hpp, src/bead_output.hpp).
#include "src/core/types.hpp"

#include <algorithm>
#include <cmath>

namespace dvisph {

// The surge front, robust to isolated particles: the furthest first coordinate (c(i),
// a fluid particle's x or a bead's leading edge x + r) of the body that begins at the
// most upstream particle. The particles are counted in slabs of width `bin` along x;
// the body ends where `gap` slabs in a row hold none (bin = dx and gap = the kernel
// radius over dx, rounded up: what lies beyond has no neighbour in the body). Spray,
// a bead or a droplet thrown ahead, then does not count as the front.
// Members of the set: c(i) > -1e299 (others return -1e300).
template <class Space>
class ConnectedFront {
 public:
  using memory_space = typename Space::memory_space;
  ConnectedFront(Real lo, Real hi, Real bin, int gap)
      : lo_(lo), bin_(bin), gap_(gap),
        count_("dvisph::metrics::front_slabs", std::max(1, int(std::ceil((hi - lo) / bin)))),
        host_(Kokkos::create_mirror_view(count_)) {}

  // The front (-1e300 where the set is empty).
  template <class Coordinate>
  Real operator()(const Coordinate& c, int n) const {
    const auto count = count_;
    const Real lo = lo_, bin = bin_;
    const int slabs = static_cast<int>(count.extent(0));
    Kokkos::deep_copy(count, 0);
    Kokkos::parallel_for(
        "dvisph::metrics::front_slabs", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          const Real xi = c(i);
          if (!(xi > -1e299)) return;
          const int b = static_cast<int>(math::floor((xi - lo) / bin));
          Kokkos::atomic_increment(&count(b < 0 ? 0 : b < slabs ? b : slabs - 1));
        });
    Kokkos::deep_copy(host_, count);
    int first = 0;
    while (first < slabs && host_(first) == 0) ++first;
    if (first == slabs) return -1e300;
    int end = first, empty = 0;  // end: one past the body's last slab
    for (int b = first; b < slabs && empty < gap_; ++b) {
      if (host_(b) > 0) end = b + 1, empty = 0;
      else ++empty;
    }
    const Real cut = end < slabs ? lo + end * bin : 1e300;
    Real front = -1e300;
    Kokkos::parallel_reduce(
        "dvisph::metrics::front", Kokkos::RangePolicy<Space>(0, n),
        KOKKOS_LAMBDA(int i, Real& m) {
          const Real xi = c(i);
          if (xi < cut && xi > m) m = xi;
        },
        Kokkos::Max<Real>(front));
    return front;
  }

 private:
  Real lo_, bin_;
  int gap_;
  Kokkos::View<int*, memory_space> count_;
  typename Kokkos::View<int*, memory_space>::HostMirror host_;
};

// c(i) of ConnectedFront: the fluid particles of an SPH set, and the leading edges of beads.
template <class X, class KindV>
struct FluidFrontCoordinate {
  X x;
  KindV kind;
  KOKKOS_INLINE_FUNCTION Real operator()(int i) const { return kind(i) == Kind::fluid ? x(i, 0) : -1e300; }
};

template <class X, class R>
struct LeadingEdge {
  X x;
  R radius;
  KOKKOS_INLINE_FUNCTION Real operator()(int i) const { return x(i, 0) + radius(i); }
};

}  // namespace dvisph
