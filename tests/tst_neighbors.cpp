// Neighbour search: the cell sweep and the stored list find exactly the brute-force
// pair set, in 2D and 3D, in a non-cubic box, with particles on cell faces, for a
// query set with a radius other than the cell size, and across periodic faces (pairs at
// their nearest image). The half split of the stored list holds each pair once.
#include "src/core/half_pairs.hpp"
#include "src/core/neighbor_list.hpp"
#include "solvers/isph/wet_cells.hpp"
#include "tests/test_space.hpp"

#include <catch2/catch.hpp>

#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace dvisph;
using Mem = typename TestSpace::memory_space;

namespace {

template <int D>
std::vector<Vec<D>> random_points(int n, const Vec<D>& hi, Real cell, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(0, 1);
  std::vector<Vec<D>> p(n);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < D; ++k) {
      p[i][k] = u(rng) * hi[k];
      if (i % 5 == 0 && k == i % D) p[i][k] = cell * std::floor(p[i][k] / cell);  // on a face
    }
  return p;
}

template <int D>
Kokkos::View<Real* [D], Mem> to_view(const std::vector<Vec<D>>& p) {
  Kokkos::View<Real* [D], Mem> x("x", p.size());
  auto h = Kokkos::create_mirror_view(x);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < D; ++k) h(i, k) = p[i][k];
  Kokkos::deep_copy(x, h);
  return x;
}

// pairs within radius, at the nearest image along the axes in `periodic` (bit k: axis k
// wraps over [0, hi[k]))
template <int D>
std::set<std::pair<int, int>> brute_force(const std::vector<Vec<D>>& q, const std::vector<Vec<D>>& t,
                                          Real radius, unsigned periodic = 0, Vec<D> hi = {}) {
  std::set<std::pair<int, int>> pairs;
  for (std::size_t i = 0; i < q.size(); ++i)
    for (std::size_t j = 0; j < t.size(); ++j) {
      Vec<D> d = q[i] - t[j];
      for (int k = 0; k < D; ++k)
        if (periodic >> k & 1u) d[k] -= hi[k] * std::round(d[k] / hi[k]);
      if (dot(d, d) < radius * radius) pairs.emplace(i, j);
    }
  return pairs;
}

// Pairs found by a sweep, gathered through a CSR list built from it.
template <int D, class Sweep, class XView>
std::set<std::pair<int, int>> swept_pairs(const Sweep& sweep, const XView& xq, int n) {
  Kokkos::View<int*, Mem> count("count", n);
  Kokkos::parallel_for(
      Kokkos::RangePolicy<TestSpace>(0, n), KOKKOS_LAMBDA(int i) {
        int c = 0;
        sweep.for_each(i, row<D>(xq, i), [&](int, const Vec<D>&, Real) { ++c; });
        count(i) = c;
      });
  auto hc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), count);
  std::vector<int> off(n + 1, 0);
  for (int i = 0; i < n; ++i) off[i + 1] = off[i] + hc(i);
  Kokkos::View<int*, Mem> offsets("offsets", n + 1), js("js", off[n] + 1);
  Kokkos::deep_copy(offsets, Kokkos::View<int*, Kokkos::HostSpace>(off.data(), n + 1));
  Kokkos::parallel_for(
      Kokkos::RangePolicy<TestSpace>(0, n), KOKKOS_LAMBDA(int i) {
        int a = offsets(i);
        sweep.for_each(i, row<D>(xq, i), [&](int j, const Vec<D>&, Real) { js(a++) = j; });
      });
  auto hj = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), js);
  std::set<std::pair<int, int>> pairs;
  for (int i = 0; i < n; ++i)
    for (int a = off[i]; a < off[i + 1]; ++a) {
      const bool inserted = pairs.emplace(i, hj(a)).second;
      REQUIRE(inserted);  // no pair visited twice
    }
  return pairs;
}

// Every pair (i, j), i != j, of `expected` exactly once in an upper row (j > i), and
// each lower entry of j naming the upper entry that holds (i, j), whose mirror names it back.
template <class List, class Pairs>
void check_half_pairs(const List& list, int n, const Pairs& expected) {
  HalfPairs<TestSpace> half;
  half.build(list.sweep(), n);
  const auto rows = half.rows();
  const auto h = [](const auto& v) { return Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), v); };
  const auto uo = h(rows.upper_offsets), up = h(rows.upper), lo = h(rows.lower_offsets), low = h(rows.lower),
             entry = h(rows.lower_entry), mirror = h(rows.mirror);
  std::set<std::pair<int, int>> once;
  int wrong = 0;
  for (int i = 0; i < n; ++i)
    for (int a = uo(i); a < uo(i + 1); ++a) {
      wrong += !(up(a) > i) || !expected.count({i, up(a)}) || !once.insert({i, up(a)}).second;
    }
  int mismatched = 0, unsorted = 0;
  long lower = 0;
  for (int j = 0; j < n; ++j)
    for (int b = lo(j); b < lo(j + 1); ++b, ++lower) {
      const int i = low(b), e = entry(b);
      mismatched += !(i < j && e >= uo(i) && e < uo(i + 1) && up(e) == j && mirror(e) == b);
      // ascending, so that a gather sums as a kernel visiting the particles in order does
      unsorted += b > lo(j) && !(low(b - 1) < i);
    }
  long distinct = 0;
  for (const auto& pr : expected) distinct += pr.first != pr.second;
  CHECK(wrong == 0);
  CHECK(mismatched == 0);
  CHECK(unsorted == 0);
  CHECK(2 * static_cast<long>(once.size()) == distinct);
  CHECK(lower == static_cast<long>(once.size()));
  CHECK(half.pairs() == static_cast<int>(once.size()));
}

template <int D>
void check_search(Real query_radius_factor, unsigned periodic = 0) {
  const bool check_pool = query_radius_factor == 1.0 && periodic == 0;
  const Real cell = 0.1;
  Vec<D> lo, hi;
  for (int k = 0; k < D; ++k) {
    lo[k] = 0;
    hi[k] = (k == 0 ? 1.0 : (k == 1 ? 0.53 : 0.37));  // non-cubic, not a multiple of the cell
  }
  const int n = D == 2 ? 1500 : 3000;
  const auto targets = random_points<D>(n, hi, cell, 7);
  const auto queries = random_points<D>(n / 3, hi, cell, 11);
  const Real radius = cell * query_radius_factor;

  const auto xt = to_view<D>(targets);
  const auto xq = to_view<D>(queries);
  CellList<D, TestSpace> cells(Grid<D>(lo, hi, cell, periodic));
  cells.build(xt, n);

  // the permutation holds every particle once
  auto perm = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), cells.permutation());
  std::set<int> seen(perm.data(), perm.data() + n);
  REQUIRE(static_cast<int>(seen.size()) == n);

  const CellSweep<D, TestSpace> sweep(cells, xt, radius);
  // same set
  const auto expected_self = brute_force<D>(targets, targets, radius, periodic, hi);
  CHECK(swept_pairs<D>(sweep, xt, n) == expected_self);
  // another set
  CHECK(swept_pairs<D>(sweep, xq, static_cast<int>(queries.size())) ==
        brute_force<D>(queries, targets, radius, periodic, hi));
  // stored list
  NeighborList<D, TestSpace> list;
  list.build(sweep, xt, n);
  CHECK(list.pairs() == static_cast<long>(expected_self.size()));
  CHECK(swept_pairs<D>(list.sweep(), xt, n) == expected_self);
  check_half_pairs(list, n, expected_self);

  // The next build fills the rows in place while they fit (targets moved a little);
  // rows that outgrow their room take new room from the pool (a few targets moved onto
  // one spot); where the pool does not hold them all (an eighth of them moved onto one
  // spot), it counts the rows afresh. The pairs are the brute-force ones in every case;
  // with the radius of a cell and no wrap, the counts of the moves are known:
  // `check_pool` says whether to check them.
  enum Move { little, crowd, far };
  for (const Move move : {little, crowd, far}) {
    auto moved = targets;
    std::mt19937 rng(5);
    std::uniform_real_distribution<Real> u(-0.02 * cell, 0.02 * cell);
    for (auto& p : moved)
      for (int k = 0; k < D; ++k) p[k] = std::min(std::max(p[k] + u(rng), Real(0)), hi[k] - 1e-9);
    const int onto_one_spot = move == crowd ? 12 : move == far ? n / 8 : 0;
    for (int a = 0; a < onto_one_spot; ++a) moved[a] = moved[n / 2];
    const auto xm = to_view<D>(moved);
    cells.build(xm, n);
    const long before = list.full_builds();
    list.build(CellSweep<D, TestSpace>(cells, xm, radius), xm, n);
    const auto expected = brute_force<D>(moved, moved, radius, periodic, hi);
    CHECK(list.pairs() == static_cast<long>(expected.size()));
    CHECK(swept_pairs<D>(list.sweep(), xm, n) == expected);
    check_half_pairs(list, n, expected);
    if (check_pool) {
      CHECK(list.full_builds() - before == (move == far ? 1 : 0));
      CHECK((list.pool_entries() > 0) == (move == crowd));
    }
  }
}

}  // namespace

TEST_CASE("cell sweep finds the brute-force pairs, 2D", "[neighbors]") {
  check_search<2>(1.0);
  check_search<2>(0.61);  // radius smaller than the cell
  check_search<2>(1.7);   // larger: two cells each side
}

TEST_CASE("cell sweep finds the brute-force pairs, 3D", "[neighbors]") {
  check_search<3>(1.0);
  check_search<3>(1.37);
}

TEST_CASE("cell sweep finds the brute-force pairs across periodic faces", "[neighbors]") {
  // the sides are not multiples of the cell: the last cell along a periodic axis is wider
  check_search<2>(1.0, 0b01);
  check_search<2>(1.7, 0b11);  // two cells each side, 5 cells along y: just enough
  check_search<3>(1.0, 0b101);
  check_search<3>(1.37, 0b011);  // 3 cells along z: reach 2 would wrap onto itself
  check_search<3>(1.0, 0b111);
  // a periodic axis shorter than 2 search radii and a cell would count pairs twice
  Vec<2> lo{{0, 0}}, hi{{1.0, 0.25}};
  CellList<2, TestSpace> cells(Grid<2>(lo, hi, 0.1, 0b10));
  const auto x = to_view<2>(random_points<2>(10, hi, 0.1, 3));
  cells.build(x, 10);
  CHECK_THROWS_AS((CellSweep<2, TestSpace>(cells, x, 0.1)), std::invalid_argument);
}

TEST_CASE("periodic positions wrap into the box, pair vectors to the nearest image", "[neighbors]") {
  const Periodic<2> p(Vec<2>{{-1, 0}}, Vec<2>{{2, 1}}, 0b01);
  CHECK(p.wrap(2.5, 0) == Approx(-0.5));
  CHECK(p.wrap(-1.25, 0) == Approx(1.75));
  CHECK(p.wrap(2.0, 0) == -1.0);   // the upper face is the lower one
  CHECK(p.wrap(5.0, 1) == 5.0);    // axis 1 does not wrap
  Vec<2> d{{2.9, 0.9}};
  p.nearest_image(d);
  CHECK(d[0] == Approx(-0.1));
  CHECK(d[1] == 0.9);
}

namespace {

// WetCells' test against its definition: a particle is near when it is water or a cell
// within `reach` cells along every axis (at the nearest image on periodic axes) of its own
// holds water.
template <int D>
void check_wet_cells(const Vec<D>& hi, Real cell, Real radius, unsigned periodic, unsigned seed) {
  const int n = 1200;
  const auto p = random_points<D>(n, hi, cell, seed);
  const Grid<D> grid(Vec<D>::zero(), hi, cell, periodic);
  std::mt19937 rng(seed + 1);
  Kokkos::View<Kind*, Mem> kind("kind", n);
  auto kh = Kokkos::create_mirror_view(kind);
  for (int i = 0; i < n; ++i) kh(i) = rng() % 150 == 0 ? Kind::fluid : Kind::wall;  // a few wet cells
  Kokkos::deep_copy(kind, kh);
  const auto x = to_view<D>(p);
  WetCells<D, TestSpace> wet;
  const auto near = wet.mark(grid, radius, x, kind, n);
  for (int margin : {0, 2}) {
    const auto test = margin == 0 ? near : wet.wider(near, margin);
    Kokkos::View<int*, Mem> got("got", n);
    Kokkos::parallel_for(
        "test::wet_cells", Kokkos::RangePolicy<TestSpace>(0, n), KOKKOS_LAMBDA(int i) { got(i) = test(i); });
    auto gh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), got);
    const int reach = grid.reach(radius) + margin;
    auto coord = [&](const Vec<D>& q, int k) { return grid.clamp(grid.coord(q[k], k), k); };
    int near_count = 0;
    for (int i = 0; i < n; ++i) {
      bool expect = kh(i) == Kind::fluid;
      for (int j = 0; j < n && !expect; ++j) {
        if (kh(j) != Kind::fluid) continue;
        bool within = true;
        for (int k = 0; k < D; ++k) {
          int d = std::abs(coord(p[i], k) - coord(p[j], k));
          if (periodic >> k & 1u) d = std::min(d, grid.ncell[k] - d);
          within = within && d <= reach;
        }
        expect = within;
      }
      near_count += expect;
      CHECK(gh(i) == int(expect));
    }
    CHECK(near_count > 0);
    CHECK(near_count < n);
  }
}

}  // namespace

TEST_CASE("wet cells: the particles within reach of water, as their definition says", "[neighbors]") {
  check_wet_cells<2>({2.0, 1.2}, 0.05, 0.1, 0, 7);
  check_wet_cells<2>({2.0, 1.2}, 0.05, 0.1, 1u, 8);  // x wraps
  check_wet_cells<3>({1.0, 0.8, 0.8}, 0.05, 0.1, 0, 9);
  check_wet_cells<3>({1.0, 0.8, 0.8}, 0.05, 0.1, 2u, 10);  // y wraps
}
