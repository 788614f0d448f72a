// Checkpoint and restart: a run saved to a file half way and continued by a new
// solver from it ends in exactly the state of the run that went straight through.
#include "kernels/wendland_c2.hpp"
#include "solvers/isph/isph_solver.hpp"
#include "src/scene_beads.hpp"
#include "tests/coupled_scenes.hpp"
#include "tests/test_space.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

#include <unistd.h>

using namespace dvisph;

namespace {

// A small dam break with a gate, viscosity and frequent reordering: every piece of
// state a restart must carry is exercised.
const char* dam_break = R"(
dimension: 2
end_time: 1
geometry:
  spacing: 0.005
  tank: {lo: [0, 0], hi: [0.2, 0.1]}
  fluid: [{lo: [0, 0], hi: [0.05, 0.05]}]
  gate: {x: 0.05, remove_at: 0.01}
numerics: {reorder_every: 7}
)";

// A jittered heap of beads falling into a box, with friction and rotation.
const char* bead_heap = R"(
dimension: 3
end_time: 1
geometry:
  tank: {lo: [0, 0, 0], hi: [0.02, 0.02, 0.04]}
solids:
  diameter: 0.0027
  lattice: [{lo: [0, 0, 0], hi: [0.02, 0.02, 0.02]}]
  jitter: 0.04
)";

// One name per process: the test executables of each backend run at once under ctest -j.
std::string temp_file(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (std::to_string(::getpid()) + "_" + name)).string();
}

template <class View>
void require_identical(const View& a, const View& b, const std::string& what) {
  Checkpoint ca, cb;  // element by element, whatever the layout
  ca.put("a", a);
  cb.put("a", b);
  const auto va = ca.values<typename View::value_type>("a"), vb = cb.values<typename View::value_type>("a");
  REQUIRE(va.size() == vb.size());
  std::size_t differ = 0;
  for (std::size_t k = 0; k < va.size(); ++k) differ += va[k] != vb[k];
  INFO(what);
  REQUIRE(differ == 0);
}

// The water of two solvers, the rows in use (after a gate went, the views' tails hold
// stale values): same step, time, count, and bits of x, v, id and pressure.
template <class Solver>
void require_identical_water(const Solver& a, const Solver& b) {
  REQUIRE(a.info().step == b.info().step);
  REQUIRE(a.info().t == b.info().t);
  REQUIRE(a.size() == b.size());
  const auto rows = Kokkos::make_pair(0, b.size());
  const auto& pa = a.particles();
  const auto& pb = b.particles();
  require_identical(Kokkos::subview(pa.x, rows, Kokkos::ALL), Kokkos::subview(pb.x, rows, Kokkos::ALL), "x");
  require_identical(Kokkos::subview(pa.v, rows, Kokkos::ALL), Kokkos::subview(pb.v, rows, Kokkos::ALL), "v");
  require_identical(Kokkos::subview(pa.id, rows), Kokkos::subview(pb.id, rows), "id");
  require_identical(Kokkos::subview(a.pressure(), rows, Kokkos::ALL),
                    Kokkos::subview(b.pressure(), rows, Kokkos::ALL), "pressure");
}

}  // namespace

// Once with one pressure solve, once with the dual-velocity step (two solves, the
// transport velocity moving the particles).
TEST_CASE("ISPH restart from a checkpoint file is bit-identical", "[checkpoint]") {
  const auto dual = GENERATE(false, true);
  INFO((dual ? "alpha = 0, beta = 0.5" : "alpha = beta"));
  const Scene s = dual ? parse_scene(dam_break, {"numerics.alpha=0", "numerics.beta=0.5"})
                       : parse_scene(dam_break);
  using Solver = IsphSolver<2, WendlandC2<2>, TestSpace>;
  Solver straight(s), first(s);
  for (int k = 0; k < 60; ++k) straight.step();
  for (int k = 0; k < 30; ++k) first.step();
  const std::string path = temp_file("dvisph_tst_checkpoint_isph.h5");
  Checkpoint c;
  first.save(c);
  c.write(path);

  Solver resumed(s);
  resumed.restore(Checkpoint::read(path));
  for (int k = 0; k < 30; ++k) resumed.step();
  require_identical_water(resumed, straight);
  std::filesystem::remove(path);
}

TEST_CASE("DEM restart from a checkpoint file is bit-identical", "[checkpoint]") {
  const Scene s = parse_scene(bead_heap);
  auto straight = scene_dem<3, TestSpace>(s), first = scene_dem<3, TestSpace>(s);
  for (int k = 0; k < 8000; ++k) straight.step(straight.time_step());
  for (int k = 0; k < 4000; ++k) first.step(first.time_step());
  REQUIRE(first.contacts_per_bead() > 0.5);  // beads in contact: the history matters
  const std::string path = temp_file("dvisph_tst_checkpoint_dem.h5");
  Checkpoint c;
  first.save(c);
  c.write(path);

  auto resumed = scene_dem<3, TestSpace>(s);
  resumed.restore(Checkpoint::read(path));
  for (int k = 0; k < 4000; ++k) resumed.step(resumed.time_step());
  REQUIRE(resumed.time() == straight.time());
  require_identical(resumed.spheres().x, straight.spheres().x, "x");
  require_identical(resumed.spheres().v, straight.spheres().v, "v");
  require_identical(resumed.spheres().omega, straight.spheres().omega, "omega");
  std::filesystem::remove(path);
}

TEST_CASE("coupled restart (water and beads) from a checkpoint file is bit-identical", "[checkpoint]") {
  const Scene s = parse_scene(testing::coupled_blob);
  using Solver = IsphSolver<3, WendlandC2<3>, TestSpace, PorousMedium<3, TestSpace>>;
  auto straight_beads = scene_dem<3, TestSpace>(s), first_beads = scene_dem<3, TestSpace>(s);
  Solver straight(s, &straight_beads), first(s, &first_beads);
  for (int k = 0; k < 6; ++k) straight.step();
  for (int k = 0; k < 3; ++k) first.step();
  const std::string path = temp_file("dvisph_tst_checkpoint_coupled.h5");
  Checkpoint c;
  first.save(c);
  first_beads.save(c);
  c.write(path);

  auto resumed_beads = scene_dem<3, TestSpace>(s);
  Solver resumed(s, &resumed_beads);
  const Checkpoint r = Checkpoint::read(path);
  resumed_beads.restore(r);
  resumed.restore(r);
  for (int k = 0; k < 3; ++k) resumed.step();
  require_identical_water(resumed, straight);
  require_identical(resumed_beads.spheres().x, straight_beads.spheres().x, "bead x");
  require_identical(resumed_beads.spheres().v, straight_beads.spheres().v, "bead v");
  require_identical(resumed_beads.spheres().f_ext, straight_beads.spheres().f_ext, "bead f_ext");
  std::filesystem::remove(path);
}

TEST_CASE("a checkpoint keeps names, extents and values", "[checkpoint]") {
  Kokkos::View<double** [3], TestSpace::memory_space> a("a", 4, 2);
  Kokkos::View<int*, TestSpace::memory_space> b("b", 5);
  Kokkos::parallel_for(
      "fill", Kokkos::RangePolicy<TestSpace>(0, 4), KOKKOS_LAMBDA(int i) {
        for (int j = 0; j < 2; ++j)
          for (int k = 0; k < 3; ++k) a(i, j, k) = 0.1 * i - j + 1e-17 * k;
        b(i) = -7 * i;
      });
  Checkpoint c;
  c.put("group/a", a);
  c.put("b", b);
  c.set("t", 0.125);
  c.set_text("scene", "name: x\n");
  const std::string path = temp_file("dvisph_tst_checkpoint_arrays.h5");
  c.write(path);
  const Checkpoint r = Checkpoint::read(path);
  Kokkos::View<double** [3], TestSpace::memory_space> a2("a2", 4, 2);
  Kokkos::View<int*, TestSpace::memory_space> b2("b2", 5);
  r.get("group/a", a2);
  r.get("b", b2);
  require_identical(a2, a, "a");
  require_identical(b2, b, "b");
  CHECK(r.number("t") == 0.125);
  CHECK(r.text("scene") == "name: x\n");
  Kokkos::View<int*, TestSpace::memory_space> wrong("wrong", 4);
  CHECK_THROWS_WITH(r.get("b", wrong), Catch::Contains("other extents"));
  CHECK_THROWS_WITH(Checkpoint::read(path + ".missing"), Catch::Contains("no such file"));
  std::filesystem::remove(path);
}
