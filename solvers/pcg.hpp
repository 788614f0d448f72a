#pragma once
// Jacobi-preconditioned conjugate gradient for several right-hand sides with the
// same symmetric positive definite matrix. The operator is applied matrix-free to
// all columns at once, so the columns share every neighbour traversal; one
// right-hand side is the special case K = 1. Each column has its own CG scalars
// and stops on its own residual: relative to |b| (`tolerance`), or absolute as the
// largest |r_i| of a row (`max_tolerance`), whichever comes first.
// The absolute test lets a caller stop at a residual that means something physical
// (the PPE: the density change per step it leaves, IsphSolver::solve_pressure).
// Preconditioner: Jacobi, or (`chebyshev(degree, ratio)`) the Chebyshev polynomial of
// degree m in D^-1 A that best approximates A^-1 on [2/ratio, 2] (Saad, Iterative Methods,
// alg. 12.1, D-scaled), m - 1 more operator applications per iteration. The eigenvalues
// of D^-1 A lie in (0, 2] for any matrix whose diagonal is at least the sum of its row's
// off-diagonal magnitudes (Gershgorin), as the PPE's is; p(lambda) > 0 on (0, 2 + 2/ratio),
// so the preconditioner is SPD whatever the true spectrum, and fixed, as CG needs.
// Or any other SPD Preconditioner passed to solve (solvers/cell_multigrid.hpp).
#include "src/core/types.hpp"

#include <cmath>
#include <string>

namespace dvisph {

constexpr int max_rhs = 2;

// N sums and M maxima (of non-negative values) in one reduction (Kokkos 3.x has no
// multiple-reducer parallel_reduce and joins through volatile references).
template <int N, int M = 0>
struct Sums {
  Real v[N], m[M > 0 ? M : 1];
  KOKKOS_INLINE_FUNCTION Sums() {
    for (int k = 0; k < N; ++k) v[k] = 0;
    for (int k = 0; k < M; ++k) m[k] = 0;
  }
  KOKKOS_INLINE_FUNCTION Sums& operator+=(const Sums& o) {
    for (int k = 0; k < N; ++k) v[k] += o.v[k];
    for (int k = 0; k < M; ++k) m[k] = m[k] < o.m[k] ? o.m[k] : m[k];
    return *this;
  }
  KOKKOS_INLINE_FUNCTION void operator+=(const volatile Sums& o) volatile {
    for (int k = 0; k < N; ++k) v[k] += o.v[k];
    for (int k = 0; k < M; ++k) m[k] = m[k] < o.m[k] ? o.m[k] : m[k];
  }
};
using ColumnSums = Sums<max_rhs>;
using UpdateSums = Sums<2 * max_rhs, max_rhs>;  // r.z, r.r, then max |r_i| per column

struct CgResult {
  int iterations = 0;
  Real residual[max_rhs] = {};      // final relative residuals
  Real max_residual[max_rhs] = {};  // final max |r_i|
  bool converged = false;
};

// Another preconditioner than the built-in ones (e.g. solvers/cell_multigrid.hpp):
// z = M^-1 r on the first n rows (q is scratch), returning r.z per column; M must be
// symmetric positive definite and the same at every iteration.
template <class Space>
struct Preconditioner {
  using Vectors = Kokkos::View<Real**, typename Space::memory_space>;
  virtual ~Preconditioner() = default;
  virtual ColumnSums apply(const Vectors& r, const Vectors& z, const Vectors& q, int n) = 0;
};

template <class Space>
class ConjugateGradient {
 public:
  using memory_space = typename Space::memory_space;
  using Vectors = Kokkos::View<Real**, memory_space>;
  using Diagonal = Kokkos::View<Real*, memory_space>;

  // degree <= 1: Jacobi. ratio: the interval's upper end over its lower end.
  void chebyshev(int degree, Real ratio) {
    degree_ = degree;
    ratio_ = ratio;
  }

  void resize(int n, int k) {
    const bool polynomial = degree_ > 1;
    if (static_cast<int>(r_.extent(0)) == n && static_cast<int>(r_.extent(1)) == k &&
        (static_cast<int>(d_.extent(0)) == n) == polynomial)
      return;
    r_ = Vectors("dvisph::pcg::r", n, k);
    z_ = Vectors("dvisph::pcg::z", n, k);
    p_ = Vectors("dvisph::pcg::p", n, k);
    q_ = Vectors("dvisph::pcg::q", n, k);
    s_ = polynomial ? Vectors("dvisph::pcg::chebyshev_residual", n, k) : Vectors();
    d_ = polynomial ? Vectors("dvisph::pcg::chebyshev_step", n, k) : Vectors();
  }

  // z = p(D^-1 A) D^-1 r, the Chebyshev preconditioner (q is scratch); returns r.z.
  template <class Operator>
  ColumnSums precondition(const Operator& A, const Diagonal& diag, const Vectors& r,
                          const Vectors& z, const Vectors& q, int n) {
    const int K = static_cast<int>(r.extent(1));
    resize(static_cast<int>(r.extent(0)), K);
    const auto range = Kokkos::RangePolicy<Space>(0, n);
    const auto s = s_, d = d_;
    const Real hi = 2, lo = hi / ratio_, theta = (hi + lo) / 2, delta = (hi - lo) / 2;
    const Real sigma = theta / delta;
    Kokkos::parallel_for(
        "dvisph::pcg::chebyshev_start", range, KOKKOS_LAMBDA(int i) {
          const Real inv_d = diag(i) > 0 ? 1 / diag(i) : 0;
          for (int k = 0; k < K; ++k) {
            s(i, k) = r(i, k);
            d(i, k) = inv_d * r(i, k) / theta;
            z(i, k) = d(i, k);
          }
        });
    // the last step also sums r.z, so an iteration keeps Jacobi's two reductions
    Real rho = 1 / sigma;
    ColumnSums rz;
    for (int step = 1; step < degree_; ++step) {
      A.apply(d, q, diag, n);
      const Real rho_new = 1 / (2 * sigma - rho), keep = rho_new * rho, push = 2 * rho_new / delta;
      rho = rho_new;
      if (step < degree_ - 1)
        Kokkos::parallel_for(
            "dvisph::pcg::chebyshev_step", range,
            KOKKOS_LAMBDA(int i) { chebyshev_row(i, K, keep, push, diag, q, s, d, z); });
      else
        Kokkos::parallel_reduce(
            "dvisph::pcg::chebyshev_last_step", range,
            KOKKOS_LAMBDA(int i, ColumnSums& sum) {
              chebyshev_row(i, K, keep, push, diag, q, s, d, z);
              for (int k = 0; k < K; ++k) sum.v[k] += r(i, k) * z(i, k);
            },
            rz);
    }
    return rz;
  }

  // One Chebyshev step at row i: s -= A d (in q), d = keep d + push D^-1 s, z += d.
  KOKKOS_INLINE_FUNCTION static void chebyshev_row(int i, int K, Real keep, Real push,
                                                   const Diagonal& diag, const Vectors& q,
                                                   const Vectors& s, const Vectors& d,
                                                   const Vectors& z) {
    const Real inv_d = diag(i) > 0 ? 1 / diag(i) : 0;
    for (int k = 0; k < K; ++k) {
      s(i, k) -= q(i, k);
      d(i, k) = keep * d(i, k) + push * inv_d * s(i, k);
      z(i, k) += d(i, k);
    }
  }

  // Solves A x = b for every column of b (n x K, K <= max_rhs); x holds the initial
  // guess. `A.apply(p, q, diag, n)` computes q = A p; rows whose diag is zero are
  // inactive (their x, b stay zero). A column stops when its residual relative to |b|
  // is below `tolerance` or its largest |r_i| below `max_tolerance` (0: that test is
  // off). Returns iterations and the final residuals. `m`, where given, replaces the
  // Jacobi or Chebyshev preconditioner.
  // (An operator object, not a closure: nvcc's device lambdas may not sit in a
  // function templated on a function-local type.)
  template <class Operator>
  CgResult solve(const Operator& A, const Diagonal& diag, const Vectors& b, const Vectors& x,
                 int n, Real tolerance, int max_iterations, Real max_tolerance = 0,
                 Preconditioner<Space>* m = nullptr) {
    const int K = static_cast<int>(b.extent(1));
    resize(static_cast<int>(b.extent(0)), K);
    auto r = r_, z = z_, p = p_, q = q_;
    const auto range = Kokkos::RangePolicy<Space>(0, n);

    A.apply(x, q, diag, n);
    Sums<3 * max_rhs, max_rhs> init;  // r.z, b.b, r.r; max |r_i|
    Kokkos::parallel_reduce(
        "dvisph::pcg::init", range,
        KOKKOS_LAMBDA(int i, Sums<3 * max_rhs, max_rhs>& s) {
          const Real inv_d = diag(i) > 0 ? 1 / diag(i) : 0;
          for (int k = 0; k < K; ++k) {
            r(i, k) = diag(i) > 0 ? b(i, k) - q(i, k) : 0;
            z(i, k) = inv_d * r(i, k);
            p(i, k) = z(i, k);
            s.v[k] += r(i, k) * z(i, k);
            s.v[max_rhs + k] += b(i, k) * b(i, k);
            s.v[2 * max_rhs + k] += r(i, k) * r(i, k);
            s.m[k] = math::max(s.m[k], math::abs(r(i, k)));
          }
        },
        init);
    ColumnSums rz, bb, rr;
    for (int k = 0; k < K; ++k)
      rz.v[k] = init.v[k], bb.v[k] = init.v[max_rhs + k], rr.v[k] = init.v[2 * max_rhs + k];
    if (m || degree_ > 1) {
      rz = m ? m->apply(r, z, q, n) : precondition(A, diag, r, z, q, n);
      Kokkos::deep_copy(p, z);
    }

    CgResult result;
    Real norm_b[max_rhs], res[max_rhs], worst[max_rhs];
    for (int k = 0; k < K; ++k) worst[k] = init.m[k];
    bool active[max_rhs];
    auto all_done = [&]() {
      bool done = true;
      for (int k = 0; k < K; ++k) {
        norm_b[k] = std::sqrt(bb.v[k]);
        res[k] = norm_b[k] > 0 ? std::sqrt(rr.v[k]) / norm_b[k] : std::sqrt(rr.v[k]);
        active[k] = res[k] > tolerance && !(worst[k] < max_tolerance);
        done = done && !active[k];
      }
      return done;
    };
    bool done = all_done();
    int it = 0;
    for (; it < max_iterations && !done; ++it) {
      A.apply(p, q, diag, n);
      ColumnSums pq;
      Kokkos::parallel_reduce(
          "dvisph::pcg::pq", range,
          KOKKOS_LAMBDA(int i, ColumnSums& s) {
            for (int k = 0; k < K; ++k) s.v[k] += p(i, k) * q(i, k);
          },
          pq);
      ColumnSums alpha;
      for (int k = 0; k < K; ++k) alpha.v[k] = active[k] && pq.v[k] > 0 ? rz.v[k] / pq.v[k] : 0;
      UpdateSums update;  // new r.z, then r.r, then max |r_i|
      Kokkos::parallel_reduce(
          "dvisph::pcg::update", range,
          KOKKOS_LAMBDA(int i, UpdateSums& s) {
            const Real inv_d = diag(i) > 0 ? 1 / diag(i) : 0;
            for (int k = 0; k < K; ++k) {
              x(i, k) += alpha.v[k] * p(i, k);
              r(i, k) -= alpha.v[k] * q(i, k);
              z(i, k) = inv_d * r(i, k);
              s.v[k] += r(i, k) * z(i, k);
              s.v[max_rhs + k] += r(i, k) * r(i, k);
              s.m[k] = math::max(s.m[k], math::abs(r(i, k)));
            }
          },
          update);
      ColumnSums rz_new;
      for (int k = 0; k < K; ++k)
        rz_new.v[k] = update.v[k], rr.v[k] = update.v[max_rhs + k], worst[k] = update.m[k];
      done = all_done();
      if (done) {
        ++it;
        break;
      }
      if (m) rz_new = m->apply(r, z, q, n);
      else if (degree_ > 1) rz_new = precondition(A, diag, r, z, q, n);
      ColumnSums beta;
      for (int k = 0; k < K; ++k) beta.v[k] = rz.v[k] > 0 ? rz_new.v[k] / rz.v[k] : 0;
      rz = rz_new;
      Kokkos::parallel_for(
          "dvisph::pcg::direction", range, KOKKOS_LAMBDA(int i) {
            for (int k = 0; k < K; ++k) p(i, k) = z(i, k) + beta.v[k] * p(i, k);
          });
    }
    result.iterations = it;
    result.converged = done;
    for (int k = 0; k < K; ++k) result.residual[k] = res[k], result.max_residual[k] = worst[k];
    return result;
  }

  std::size_t bytes() const { return view_bytes(r_, z_, p_, q_, s_, d_); }

 private:
  Vectors r_, z_, p_, q_;
  Vectors s_, d_;  // the Chebyshev preconditioner's residual and step
  int degree_ = 1;
  Real ratio_ = 30;
};

}  // namespace dvisph
