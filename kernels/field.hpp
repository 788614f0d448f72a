#pragma once
// Uniform access to per-particle fields of any rank: a scalar field is an (n) view,
// a vector or multi-column field an (n x c) view. Operators loop over components.
#include "src/core/types.hpp"

namespace dvisph {

constexpr int max_components = 4;

template <class V>
KOKKOS_INLINE_FUNCTION int components(const V& v) {
  if constexpr (int(V::traits::rank) == 1) return 1;
  else return static_cast<int>(v.extent(1));
}
template <class V>
KOKKOS_INLINE_FUNCTION auto& at(const V& v, int i, int c) {
  if constexpr (int(V::traits::rank) == 1) return v(i);
  else return v(i, c);
}

}  // namespace dvisph
