#pragma once
// The matrix A of PressurePoisson with its off-diagonal coefficients stored (CSR over
// the unknown rows, in the neighbour list's pair order). Built once per step, it turns
// each CG mat-vec into a read of weights and columns instead of a distance and a
// kernel derivative per pair: 3-8x faster on CPU (benchmarks/RESULTS.md), at 12 bytes
// per pair (3D: ~1.4 kB per particle). The matrix-free operator stays the choice where
// memory is short (numerics.pressure_operator).
#include "solvers/isph/pressure_poisson.hpp"
#include "src/core/csr_rows.hpp"

namespace dvisph {

template <class Space>
class PoissonMatrix {
 public:
  using memory_space = typename Space::memory_space;

  // Row i's length: the off-diagonal coefficients of `ppe`'s row i.
  template <class Ppe>
  struct CoefficientCount {
    Ppe ppe;
    KOKKOS_INLINE_FUNCTION int operator()(int i) const {
      int count = 0;
      ppe.for_each_coefficient(i, [&](int, Real) { ++count; });
      return count;
    }
  };

  // The coefficients of `ppe`'s operator over its first n particles (diag from assemble).
  template <class Ppe>
  void build(const Ppe& ppe, int n) {
    const int total =
        csr_offsets<Space>(offsets_, n, CoefficientCount<Ppe>{ppe}, "dvisph::poisson_matrix");
    reserve_entries(columns_, total, "dvisph::poisson_matrix::columns");
    reserve_entries(values_, total, "dvisph::poisson_matrix::values");
    auto offsets = offsets_;
    auto columns = columns_;
    auto values = values_;
    Kokkos::parallel_for(
        "dvisph::poisson_matrix::fill", RowPolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          int a = offsets(i);
          ppe.for_each_coefficient(i, [&](int j, Real w) {
            columns(a) = j;
            values(a++) = w;
          });
        });
    nonzeros_ = total;
  }

  // q = A p for all columns, the same sums in the same order as PressurePoisson::apply.
  // The column count is a template argument, so that the inner loop over columns is
  // unrolled (with it a runtime count, the two-column apply cost 1.6-1.8 times the
  // one-column one per CG iteration on the 3D paper's case; the sums are the same).
  template <class P, class Diag>
  void apply(const P& p, const P& q, const Diag& diag, int n) const {
    static_assert(max_rhs == 2, "apply dispatches on 1 or 2 columns");
    if (p.extent(1) == 1) apply_columns<1>(p, q, diag, n);
    else apply_columns<2>(p, q, diag, n);
  }

  template <int K, class P, class Diag>
  void apply_columns(const P& p, const P& q, const Diag& diag, int n) const {
    const auto offsets = offsets_;
    const auto columns = columns_;
    const auto values = values_;
    Kokkos::parallel_for(
        "dvisph::poisson_matrix::apply", RowPolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          Real sum[K] = {};
          for (int a = offsets(i); a < offsets(i + 1); ++a)
            for (int k = 0; k < K; ++k) sum[k] += values(a) * p(columns(a), k);
          for (int k = 0; k < K; ++k) q(i, k) = sum[k] + diag(i) * p(i, k);
        });
  }

  long nonzeros() const { return nonzeros_; }
  std::size_t bytes() const { return view_bytes(offsets_, columns_, values_); }
  Kokkos::View<const int*, memory_space> offsets() const { return offsets_; }
  Kokkos::View<const int*, memory_space> columns() const { return columns_; }
  Kokkos::View<const Real*, memory_space> values() const { return values_; }

 private:
  Kokkos::View<int*, memory_space> offsets_, columns_;
  Kokkos::View<Real*, memory_space> values_;
  long nonzeros_ = 0;
};

}  // namespace dvisph
