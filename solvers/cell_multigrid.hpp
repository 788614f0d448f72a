#pragma once
// A multilevel preconditioner for the stored PPE matrix: aggregation on the cells of a
// grid. Level 1 aggregates the unknowns by the grid cell they lie in, max(4 dx, kernel
// radius) wide (4^D lattice sites; in a trial build on the 3D dam break, 2 dx cells
// took 10.3 CG iterations a step against 11.6, at more set-up); each coarser level
// aggregates 2^D cells of the one below. A coarse operator is the Galerkin product P^T A P of the
// piecewise-constant aggregation P; a row couples only the cells next to it (its
// stencil, s = 1). One application is a symmetric V-cycle: one damped
// Jacobi sweep before and one after the coarse correction on every level, a few sweeps
// on the coarsest. Or (FineLevel::additive) the particles take no smoothing sweeps: z =
// omega D^-1 r + P B_1 P^T r, B_1 the V-cycle from level 1 down. That spares the two
// matrix applications on the particles that a smoothed application costs, for more CG
// iterations (3D dam break: 19.9 a step against 11.6, PPE 0.86-0.87 of the time;
// benchmarks/RESULTS.md); the sum of two SPD operators is SPD.
// Why it is a valid CG preconditioner: the PPE matrix is an M-matrix (off-diagonals
// <= 0, each diagonal at least its row's off-diagonal sum), and so is every P^T A P;
// damped Jacobi at omega = 2/3 < 2 / lambda_max(D^-1 A) (lambda_max <= 2, Gershgorin)
// converges on each, so the cycle is symmetric positive definite, and fixed.
// Every coarse sum runs over cells and their members in a fixed order (no atomics):
// the same bits on every backend and thread count. Each level's operator is stored as
// CSR (the stencil only orders a row's sums while it is built).
#include "solvers/isph/poisson_matrix.hpp"
#include "solvers/pcg.hpp"
#include "src/core/cell_list.hpp"

#include <stdexcept>
#include <vector>

namespace dvisph {

// The cells of one level and the stencil of cells within s of each.
template <int D>
struct StencilGrid {
  int n[D];
  bool wraps[D];
  int s;  // stencil half-width, in cells

  int size() const {
    int c = 1;
    for (int k = 0; k < D; ++k) c *= n[k];
    return c;
  }
  KOKKOS_INLINE_FUNCTION int width() const { return 2 * s + 1; }
  KOKKOS_INLINE_FUNCTION int slots() const {
    int c = 1;
    for (int k = 0; k < D; ++k) c *= width();
    return c;
  }
  KOKKOS_INLINE_FUNCTION int center() const { return (slots() - 1) / 2; }
  KOKKOS_INLINE_FUNCTION void coords(int c, int (&x)[D]) const {
    for (int k = 0; k < D; ++k) x[k] = c % n[k], c /= n[k];
  }
  KOKKOS_INLINE_FUNCTION int index(const int (&x)[D]) const {
    int c = 0;
    for (int k = D - 1; k >= 0; --k) c = c * n[k] + x[k];
    return c;
  }
  // Coordinates of the cell at stencil slot o from x (wrapped); false outside the grid.
  KOKKOS_INLINE_FUNCTION bool neighbor(const int (&x)[D], int o, int (&y)[D]) const {
    for (int k = 0; k < D; ++k) {
      y[k] = x[k] + o % width() - s;
      o /= width();
      if (wraps[k]) y[k] = y[k] < 0 ? y[k] + n[k] : (y[k] >= n[k] ? y[k] - n[k] : y[k]);
      else if (y[k] < 0 || y[k] >= n[k]) return false;
    }
    return true;
  }
  // The stencil slot of cell y seen from cell x; -1 beyond the stencil.
  KOKKOS_INLINE_FUNCTION int slot(const int (&x)[D], const int (&y)[D]) const {
    int o = 0, stride = 1;
    for (int k = 0; k < D; ++k) {
      int d = y[k] - x[k];
      if (wraps[k]) d = d > s ? d - n[k] : (d < -s ? d + n[k] : d);
      if (d < -s || d > s) return -1;
      o += (d + s) * stride;
      stride *= width();
    }
    return o;
  }
  // f(index, coordinates) of each cell of `fine` (the level below) that cell c of this
  // level aggregates: 2^D, fewer at the grid's far edges.
  template <class F>
  KOKKOS_INLINE_FUNCTION void for_each_child(int c, const StencilGrid& fine, F&& f) const {
    int x[D], child[D];
    coords(c, x);
    for (int b = 0; b < (1 << D); ++b) {
      bool inside = true;
      for (int k = 0; k < D; ++k) {
        child[k] = 2 * x[k] + ((b >> k) & 1);
        inside = inside && child[k] < fine.n[k];
      }
      if (inside) f(fine.index(child), child);
    }
  }
  // The next level: 2^D cells in one, stencil half-width (s + 1) / 2.
  StencilGrid coarser() const {
    StencilGrid c = *this;
    for (int k = 0; k < D; ++k) c.n[k] = (n[k] + 1) / 2;
    c.s = (s + 1) / 2;
    return c;
  }
  // A wrapped axis needs distinct cells across the stencil.
  bool fits() const {
    for (int k = 0; k < D; ++k)
      if (wraps[k] && n[k] < 2 * s + 1) return false;
    return true;
  }
};

// The stencil a row is summed in: s = 1 on every level.
template <int D>
constexpr int max_stencil_slots = D == 2 ? 9 : 27;

template <int D, class Space>
class CellMultigrid final : public Preconditioner<Space> {
 public:
  using memory_space = typename Space::memory_space;
  using Vectors = Kokkos::View<Real**, memory_space>;
  using Diagonal = Kokkos::View<Real*, memory_space>;
  using Indices = Kokkos::View<int*, memory_space>;
  static constexpr Real omega = 2.0 / 3.0;
  enum class FineLevel { smoothed, additive };

  // Aggregates max(4 dx, radius) wide over the particles' box (periodic_axes: bit k
  // where axis k wraps), for a matrix whose couplings reach `radius`; up to max_levels
  // levels, `coarsest_sweeps` Jacobi sweeps on the last.
  CellMultigrid(const Vec<D>& box_lo, const Vec<D>& box_hi, unsigned periodic_axes, Real dx,
                Real radius, FineLevel fine = FineLevel::smoothed, int max_levels = 10,
                int coarsest_sweeps = 4)
      : cells_(Grid<D>(box_lo, box_hi, std::max(4 * dx, radius), periodic_axes)),
        fine_(fine),
        max_levels_(max_levels),
        coarsest_sweeps_(coarsest_sweeps) {
    const Grid<D>& grid = cells_.grid();
    for (int k = 0; k < D; ++k) first_.n[k] = grid.ncell[k], first_.wraps[k] = grid.periodic.wraps(k);
    first_.s = grid.reach(radius);
    if (first_.slots() > max_stencil_slots<D>)
      throw std::invalid_argument("CellMultigrid: couplings reach beyond the next aggregate");
    if (!first_.fits())
      throw std::invalid_argument("CellMultigrid: a periodic axis holds fewer than " +
                                  std::to_string(first_.width()) + " aggregates");
  }

  // Sets up the levels for the stored matrix with diagonal diag over particles x
  // (rows with diag 0 take no part), for K right-hand sides.
  template <class X>
  void build(const PoissonMatrix<Space>& matrix, const Diagonal& diag, const X& x, int n, int K) {
    matrix_ = matrix;
    diag_ = diag;
    cells_.build(x, n);
    if (static_cast<int>(aggregate_.extent(0)) < n)
      aggregate_ = Indices(Kokkos::view_alloc(Kokkos::WithoutInitializing, "dvisph::multigrid::aggregate"), n);
    const auto grid = cells_.grid();
    if (static_cast<int>(place_.extent(0)) < n)
      place_ = decltype(place_)(Kokkos::view_alloc(Kokkos::WithoutInitializing, "dvisph::multigrid::place"), n);
    const auto aggregate = aggregate_;
    const auto place = place_;
    Kokkos::parallel_for(
        "dvisph::multigrid::aggregate", Kokkos::RangePolicy<Space>(0, n), KOKKOS_LAMBDA(int i) {
          Real xi[D];
          for (int k = 0; k < D; ++k) xi[k] = x(i, k);
          const bool active = diag(i) > 0;
          aggregate(i) = active ? grid.cell_of(xi) : -1;
          for (int k = 0; k < D; ++k) place(i, k) = active ? grid.clamp(grid.coord(xi[k], k), k) : 0;
        });
    if (levels_.empty() || static_cast<int>(levels_[0].r.extent(1)) != K) allocate(K);
    FromParticles from{levels_[0].grid, cells_.offsets(), cells_.permutation(), diag, aggregate_, place_,
                       matrix.offsets(), matrix.columns(), matrix.values(), status_};
    compress(levels_[0], from, "dvisph::multigrid::galerkin_from_particles");
    for (std::size_t l = 1; l < levels_.size(); ++l) {
      const Level& F = levels_[l - 1];
      FromCells coarse{levels_[l].grid, F.grid, F.offsets, F.columns, F.values, F.diag, status_};
      compress(levels_[l], coarse, "dvisph::multigrid::galerkin_from_cells");
    }
    int bad = 0;
    Kokkos::deep_copy(bad, status_);
    if (bad) throw std::logic_error("CellMultigrid: a coupling reaches beyond the coarse stencil");
  }

  int levels() const { return static_cast<int>(levels_.size()); }
  std::size_t bytes() const {
    std::size_t b = cells_.bytes() + view_bytes(aggregate_, place_, status_);
    for (const auto& L : levels_) b += view_bytes(L.offsets, L.columns, L.values, L.diag, L.inv_diag, L.r, L.z, L.t);
    return b;
  }

  // z = M^-1 r on the particles, q scratch; returns r.z.
  ColumnSums apply(const Vectors& r, const Vectors& z, const Vectors& q, int n) override {
    const int K = static_cast<int>(r.extent(1));
    const auto diag = diag_;
    const auto range = Kokkos::RangePolicy<Space>(0, n);
    const auto aggregate = aggregate_;
    if (fine_ == FineLevel::additive) {
      restrict_from_particles(r, q, false);
      cycle(0);
      const auto zc = levels_[0].z;  // (after the cycle: its sweeps swap z and t)
      ColumnSums rz;
      Kokkos::parallel_reduce(
          "dvisph::multigrid::fine_additive", range,
          KOKKOS_LAMBDA(int i, ColumnSums& s) {
            const Real w = diag(i) > 0 ? omega / diag(i) : 0;
            const int c = aggregate(i);
            for (int k = 0; k < K; ++k) {
              z(i, k) = w * r(i, k) + (c >= 0 ? zc(c, k) : 0);
              s.v[k] += r(i, k) * z(i, k);
            }
          },
          rz);
      return rz;
    }
    Kokkos::parallel_for(
        "dvisph::multigrid::fine_presmooth", range, KOKKOS_LAMBDA(int i) {
          const Real w = diag(i) > 0 ? omega / diag(i) : 0;
          for (int k = 0; k < K; ++k) z(i, k) = w * r(i, k);
        });
    matrix_.apply(z, q, diag, n);
    restrict_from_particles(r, q, true);
    cycle(0);
    const auto zc = levels_[0].z;
    Kokkos::parallel_for(
        "dvisph::multigrid::prolong_to_particles", range, KOKKOS_LAMBDA(int i) {
          const int c = aggregate(i);
          if (c >= 0)
            for (int k = 0; k < K; ++k) z(i, k) += zc(c, k);
        });
    matrix_.apply(z, q, diag, n);
    ColumnSums rz;
    Kokkos::parallel_reduce(
        "dvisph::multigrid::fine_postsmooth", range,
        KOKKOS_LAMBDA(int i, ColumnSums& s) {
          const Real w = diag(i) > 0 ? omega / diag(i) : 0;
          for (int k = 0; k < K; ++k) {
            z(i, k) += w * (r(i, k) - q(i, k));
            s.v[k] += r(i, k) * z(i, k);
          }
        },
        rz);
    return rz;
  }

  // (The rest holds device lambdas and functors: public, as nvcc requires.)
  struct Level {
    StencilGrid<D> grid;
    Indices offsets, columns;  // CSR of the off-diagonal entries, by cell
    Kokkos::View<Real*, memory_space> values;
    Diagonal diag, inv_diag;  // inv_diag 0 on cells without unknowns
    Vectors r, z, t;          // cells x K
  };

  // The contributions to a level-1 row: its member particles' rows, by the aggregates of
  // their columns; f(slot, value).
  struct FromParticles {
    StencilGrid<D> grid;
    Kokkos::View<const int*, memory_space> members_offsets;
    Indices members;
    Diagonal diag;
    Indices aggregate;
    Kokkos::View<int* [D], memory_space> place;
    Kokkos::View<const int*, memory_space> rows, columns;
    Kokkos::View<const Real*, memory_space> values;
    Kokkos::View<int, memory_space> status;
    KOKKOS_INLINE_FUNCTION bool empty(int c) const {
      for (int m = members_offsets(c); m < members_offsets(c + 1); ++m)
        if (diag(members(m)) > 0) return false;
      return true;
    }
    template <class F>
    KOKKOS_INLINE_FUNCTION void operator()(int c, F&& f) const {
      int x[D], y[D];
      grid.coords(c, x);
      for (int m = members_offsets(c); m < members_offsets(c + 1); ++m) {
        const int i = members(m);
        if (!(diag(i) > 0)) continue;
        f(grid.center(), diag(i));
        for (int e = rows(i); e < rows(i + 1); ++e) {
          const int j = columns(e);
          if (aggregate(j) < 0) continue;
          for (int k = 0; k < D; ++k) y[k] = place(j, k);
          const int o = grid.slot(x, y);
          if (o < 0) status() = 1;
          else f(o, values(e));
        }
      }
    }
  };

  // The contributions to a row of level l + 1: its 2^D children's rows on level l.
  struct FromCells {
    StencilGrid<D> grid, fine;
    Indices rows, columns;
    Kokkos::View<Real*, memory_space> values;
    Diagonal diag;
    Kokkos::View<int, memory_space> status;
    KOKKOS_INLINE_FUNCTION bool empty(int c) const {
      bool none = true;
      grid.for_each_child(c, fine, [&](int i, const int(&)[D]) { none = none && diag(i) == 0; });
      return none;
    }
    template <class F>
    KOKKOS_INLINE_FUNCTION void operator()(int c, F&& f) const {
      int x[D], y[D];
      grid.coords(c, x);
      grid.for_each_child(c, fine, [&](int i, const int(&)[D]) {
        if (diag(i) != 0) f(grid.center(), diag(i));
        for (int e = rows(i); e < rows(i + 1); ++e) {
          fine.coords(columns(e), y);
          for (int k = 0; k < D; ++k) y[k] /= 2;
          const int o = grid.slot(x, y);
          if (o < 0) status() = 1;
          else f(o, values(e));
        }
      });
    }
  };

  // A row's sums in stencil order (the same order on every backend).
  template <class Source>
  struct Row {
    Real a[max_stencil_slots<D>];
    KOKKOS_INLINE_FUNCTION Row(const Source& source, int c) {
      for (int o = 0; o < source.grid.slots(); ++o) a[o] = 0;
      source(c, [&](int o, Real v) { a[o] += v; });
    }
  };
  template <class Source>
  struct CountRow {
    Source source;
    KOKKOS_INLINE_FUNCTION int operator()(int c) const {
      if (source.empty(c)) return 0;
      const Row<Source> row(source, c);
      int count = 0;
      for (int o = 0; o < source.grid.slots(); ++o) count += o != source.grid.center() && row.a[o] != 0;
      return count;
    }
  };

  // The level's CSR from its rows' sums: count, offsets, fill.
  template <class Source>
  void compress(Level& L, const Source& source, const std::string& name) {
    const int cells = L.grid.size();
    const int total = csr_offsets<Space>(L.offsets, cells, CountRow<Source>{source}, name);
    reserve_entries(L.columns, total, name + "::columns");
    reserve_entries(L.values, total, name + "::values");
    const Level view = L;
    Kokkos::parallel_for(
        name + "::fill", RowPolicy<Space>(0, cells), KOKKOS_LAMBDA(int c) {
          if (source.empty(c)) {
            view.diag(c) = view.inv_diag(c) = 0;
            return;
          }
          const Row<Source> row(source, c);
          const auto& g = source.grid;
          int x[D], y[D];
          g.coords(c, x);
          int e = view.offsets(c);
          for (int o = 0; o < g.slots(); ++o) {
            if (o == g.center() || row.a[o] == 0) continue;
            g.neighbor(x, o, y);
            view.columns(e) = g.index(y);
            view.values(e++) = row.a[o];
          }
          const Real d = row.a[g.center()];
          view.diag(c) = d;
          view.inv_diag(c) = d > 0 ? 1 / d : 0;
        });
  }

  void allocate(int K) {
    levels_.clear();
    StencilGrid<D> g = first_;
    for (int l = 0; l < max_levels_; ++l) {
      Level L;
      L.grid = g;
      const int cells = g.size();
      L.diag = Diagonal("dvisph::multigrid::diagonal", cells);
      L.inv_diag = Diagonal("dvisph::multigrid::inverse_diagonal", cells);
      L.r = Vectors("dvisph::multigrid::r", cells, K);
      L.z = Vectors("dvisph::multigrid::z", cells, K);
      L.t = Vectors("dvisph::multigrid::t", cells, K);
      levels_.push_back(L);
      const StencilGrid<D> next = g.coarser();
      if (next.size() == cells || !next.fits() || cells <= coarsest_cells) break;
      g = next;
    }
    status_ = Kokkos::View<int, memory_space>("dvisph::multigrid::status");
  }

  // r_1 = P^T (r - q) over the unknowns of each level-1 cell (P^T r without q).
  void restrict_from_particles(const Vectors& r, const Vectors& q, bool with_q) const {
    const Level L = levels_[0];
    const int K = static_cast<int>(r.extent(1));
    const auto offsets = cells_.offsets();
    const auto members = cells_.permutation();
    const auto aggregate = aggregate_;
    Kokkos::parallel_for(
        "dvisph::multigrid::restrict_from_particles", RowPolicy<Space>(0, L.grid.size()),
        KOKKOS_LAMBDA(int c) {
          Real sum[max_rhs] = {};
          for (int m = offsets(c); m < offsets(c + 1); ++m) {
            const int i = members(m);
            if (aggregate(i) < 0) continue;
            for (int k = 0; k < K; ++k) sum[k] += with_q ? r(i, k) - q(i, k) : r(i, k);
          }
          for (int k = 0; k < K; ++k) L.r(c, k) = sum[k];
        });
  }

  // (A z)(c) on a level.
  KOKKOS_INLINE_FUNCTION static Real level_apply(const Level& L, int c, int k, const Vectors& z) {
    Real sum = L.diag(c) * z(c, k);
    for (int e = L.offsets(c); e < L.offsets(c + 1); ++e) sum += L.values(e) * z(L.columns(e), k);
    return sum;
  }

  // One damped Jacobi sweep on level L: t = z + omega D^-1 (r - A z), then z and t swap.
  static void sweep(Level& L, int K) {
    const Level view = L;
    Kokkos::parallel_for(
        "dvisph::multigrid::jacobi", RowPolicy<Space>(0, L.grid.size()), KOKKOS_LAMBDA(int c) {
          const Real w = omega * view.inv_diag(c);
          for (int k = 0; k < K; ++k)
            view.t(c, k) = view.z(c, k) + w * (view.r(c, k) - level_apply(view, c, k, view.z));
        });
    std::swap(L.z, L.t);
  }

  // V-cycle on level l for its r, into its z.
  void cycle(int l) {
    Level& L = levels_[l];
    const int K = static_cast<int>(L.r.extent(1));
    const int cells = L.grid.size();
    {
      const Level view = L;
      Kokkos::parallel_for(
          "dvisph::multigrid::presmooth", Kokkos::RangePolicy<Space>(0, cells), KOKKOS_LAMBDA(int c) {
            for (int k = 0; k < K; ++k) view.z(c, k) = omega * view.inv_diag(c) * view.r(c, k);
          });
    }
    if (l + 1 == static_cast<int>(levels_.size())) {
      for (int s = 1; s < coarsest_sweeps_; ++s) sweep(L, K);
      return;
    }
    Level& C = levels_[l + 1];
    {
      const Level view = L;
      Kokkos::parallel_for(
          "dvisph::multigrid::residual", RowPolicy<Space>(0, cells), KOKKOS_LAMBDA(int c) {
            for (int k = 0; k < K; ++k) view.t(c, k) = view.r(c, k) - level_apply(view, c, k, view.z);
          });
      const Level coarse = C;
      Kokkos::parallel_for(
          "dvisph::multigrid::restrict", Kokkos::RangePolicy<Space>(0, C.grid.size()),
          KOKKOS_LAMBDA(int c) {
            Real sum[max_rhs] = {};
            coarse.grid.for_each_child(c, view.grid, [&](int f, const int(&)[D]) {
              for (int k = 0; k < K; ++k) sum[k] += view.t(f, k);
            });
            for (int k = 0; k < K; ++k) coarse.r(c, k) = sum[k];
          });
    }
    cycle(l + 1);
    {
      const Level view = L, coarse = C;
      Kokkos::parallel_for(
          "dvisph::multigrid::prolong", Kokkos::RangePolicy<Space>(0, cells), KOKKOS_LAMBDA(int c) {
            int x[D], parent[D];
            view.grid.coords(c, x);
            for (int k = 0; k < D; ++k) parent[k] = x[k] / 2;
            const int p = coarse.grid.index(parent);
            for (int k = 0; k < K; ++k) view.z(c, k) += coarse.z(p, k);
          });
    }
    sweep(L, K);
  }

  static constexpr int coarsest_cells = 64;

 private:
  CellList<D, Space> cells_;
  StencilGrid<D> first_;
  FineLevel fine_;
  int max_levels_, coarsest_sweeps_;
  std::vector<Level> levels_;
  PoissonMatrix<Space> matrix_;
  Diagonal diag_;
  Indices aggregate_;                         // each particle's level-1 cell, -1 if not an unknown
  Kokkos::View<int* [D], memory_space> place_;  // and its coordinates
  Kokkos::View<int, memory_space> status_;
};

}  // namespace dvisph
