#pragma once
// Basic types shared by every part of dvisph: the floating-point type, a small
// fixed-size vector for device code, and the particle kinds.
#include <Kokkos_Core.hpp>

#include <cstdint>

namespace dvisph {

using Real = double;

// The policy of a loop over particle rows whose cost is uneven (pair loops: most wall
// particles of a tank have no list, a fluid one ~100 pairs): rows are handed out in
// chunks as threads free up, not split evenly up front (OpenMP: 15 % off the 3D dam
// break's list build with 2 threads; GPUs ignore it). Each row is computed alone, so
// results do not depend on it.
template <class Space>
using RowPolicy = Kokkos::RangePolicy<Space, Kokkos::Schedule<Kokkos::Dynamic>>;

// Kokkos 3.x keeps math functions in Kokkos::Experimental, 4.x in Kokkos; std:: works
// on the host and, through Kokkos' wrappers, on devices for the few we need.
namespace math {
#if KOKKOS_VERSION >= 30700
namespace kmath = ::Kokkos;
#else
namespace kmath = ::Kokkos::Experimental;
#endif
KOKKOS_INLINE_FUNCTION Real sqrt(Real x) { return kmath::sqrt(x); }
KOKKOS_INLINE_FUNCTION Real floor(Real x) { return kmath::floor(x); }
KOKKOS_INLINE_FUNCTION Real log(Real x) { return kmath::log(x); }
KOKKOS_INLINE_FUNCTION Real log10(Real x) { return kmath::log10(x); }
KOKKOS_INLINE_FUNCTION Real exp(Real x) { return kmath::exp(x); }
KOKKOS_INLINE_FUNCTION Real pow(Real x, Real y) { return kmath::pow(x, y); }
KOKKOS_INLINE_FUNCTION Real sin(Real x) { return kmath::sin(x); }
KOKKOS_INLINE_FUNCTION Real cos(Real x) { return kmath::cos(x); }
KOKKOS_INLINE_FUNCTION bool isfinite(Real x) { return kmath::isfinite(x); }
KOKKOS_INLINE_FUNCTION Real abs(Real x) { return x < 0 ? -x : x; }
KOKKOS_INLINE_FUNCTION Real min(Real a, Real b) { return a < b ? a : b; }
KOKKOS_INLINE_FUNCTION Real max(Real a, Real b) { return a > b ? a : b; }
constexpr Real pi = 3.14159265358979323846;
}  // namespace math

// A D-component vector for use inside kernels (registers, not memory).
template <int D>
struct Vec {
  Real c[D];
  KOKKOS_INLINE_FUNCTION Real& operator[](int k) { return c[k]; }
  KOKKOS_INLINE_FUNCTION const Real& operator[](int k) const { return c[k]; }
  KOKKOS_INLINE_FUNCTION static Vec zero() {
    Vec v{};
    for (int k = 0; k < D; ++k) v.c[k] = 0;
    return v;
  }
};

template <int D>
KOKKOS_INLINE_FUNCTION Vec<D> operator+(Vec<D> a, const Vec<D>& b) {
  for (int k = 0; k < D; ++k) a[k] += b[k];
  return a;
}
template <int D>
KOKKOS_INLINE_FUNCTION Vec<D> operator-(Vec<D> a, const Vec<D>& b) {
  for (int k = 0; k < D; ++k) a[k] -= b[k];
  return a;
}
template <int D>
KOKKOS_INLINE_FUNCTION Vec<D> operator*(Real s, Vec<D> a) {
  for (int k = 0; k < D; ++k) a[k] *= s;
  return a;
}
template <int D>
KOKKOS_INLINE_FUNCTION Vec<D>& operator+=(Vec<D>& a, const Vec<D>& b) {
  for (int k = 0; k < D; ++k) a[k] += b[k];
  return a;
}
template <int D>
KOKKOS_INLINE_FUNCTION Real dot(const Vec<D>& a, const Vec<D>& b) {
  // from the first product, not from 0: without -ffast-math 0 + x is an add the
  // compiler must keep (it turns -0 into +0), one more latency in every dot product
  Real s = a[0] * b[0];
  for (int k = 1; k < D; ++k) s += a[k] * b[k];
  return s;
}

// Columns first .. first + N - 1 of row i of a 2D view as a Vec (e.g. one field of a
// record packed in a row), and back.
template <int N, class View>
KOKKOS_INLINE_FUNCTION Vec<N> columns(const View& v, int i, int first) {
  Vec<N> r;
  for (int k = 0; k < N; ++k) r[k] = v(i, first + k);
  return r;
}
template <int N, class View>
KOKKOS_INLINE_FUNCTION void set_columns(const View& v, int i, int first, const Vec<N>& x) {
  for (int k = 0; k < N; ++k) v(i, first + k) = x[k];
}

// Row i of an (n x D) view as a Vec.
template <int D, class View>
KOKKOS_INLINE_FUNCTION Vec<D> row(const View& v, int i) {
  return columns<D>(v, i, 0);
}

// Bytes allocated by the given views (their spans), for memory accounting.
template <class... Views>
std::size_t view_bytes(const Views&... views) {
  return (std::size_t{0} + ... + (views.span() * sizeof(typename Views::value_type)));
}

// What a particle is. A gate is a wall that a scene removes at a given time.
enum class Kind : std::uint8_t { fluid = 0, wall = 1, gate = 2, solid = 3 };
KOKKOS_INLINE_FUNCTION bool is_wall(Kind k) { return k == Kind::wall || k == Kind::gate; }

}  // namespace dvisph
