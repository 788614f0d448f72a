#pragma once
// Structure-of-arrays particle storage. The persistent state of an SPH particle set
// (fluid and wall particles together, told apart by `kind`); scratch fields of a
// solver live in the solver. Default View layouts give x(i, k) contiguous per
// particle on CPUs and coalesced per component on GPUs.
#include "src/core/types.hpp"

#include <string>

namespace dvisph {

template <int D, class Space>
struct Particles {
  using execution_space = Space;
  using memory_space = typename Space::memory_space;
  static constexpr int dim = D;

  int n = 0;
  Kokkos::View<Real* [D], memory_space> x, v;  // position [m], velocity [m/s]
  Kokkos::View<Real*, memory_space> m;          // mass [kg]
  Kokkos::View<Kind*, memory_space> kind;
  Kokkos::View<int*, memory_space> id;           // index at creation: stable through reordering

  Particles() = default;
  explicit Particles(int count, const std::string& name = "particles")
      : n(count),
        x("dvisph::" + name + "::x", count),
        v("dvisph::" + name + "::v", count),
        m("dvisph::" + name + "::m", count),
        kind("dvisph::" + name + "::kind", count),
        id("dvisph::" + name + "::id", count) {}

  // Calls f(view) on every persistent per-particle view (for reordering, checkpoints).
  template <class F>
  void for_each_field(F&& f) {
    f(x);
    f(v);
    f(m);
    f(kind);
    f(id);
  }
};

}  // namespace dvisph
