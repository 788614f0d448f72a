#pragma once
// Largest and smallest entry of a per-particle array, reduced on its own space.
// (Free functions rather than lambdas in constructors: nvcc allows device lambdas
// only in functions whose address can be taken.)
#include "src/core/types.hpp"

namespace dvisph {

template <class Space, class View>
Real max_of(const View& v, int n, const std::string& label) {
  Real result = 0;
  Kokkos::parallel_reduce(
      label, Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i, Real& m) { m = math::max(m, v(i)); }, Kokkos::Max<Real>(result));
  return result;
}

template <class Space, class View>
Real min_of(const View& v, int n, const std::string& label) {
  Real result = 0;
  Kokkos::parallel_reduce(
      label, Kokkos::RangePolicy<Space>(0, n),
      KOKKOS_LAMBDA(int i, Real& m) { m = math::min(m, v(i)); }, Kokkos::Min<Real>(result));
  return result;
}

}  // namespace dvisph
