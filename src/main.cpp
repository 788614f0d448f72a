// dvisph command line: run, check, schema.
#include "kernels/cubic_spline.hpp"
#include "kernels/wendland_c2.hpp"
#include "src/run.hpp"
#include "src/scene.hpp"
#include "src/schema.hpp"
#include "src/simulation.hpp"

#include <CLI/CLI.hpp>
#include <Kokkos_Core.hpp>
#include <fmt/core.h>
#include <unistd.h>

#include <filesystem>

namespace {

enum Exit { ok = 0, failure = 1, bad_input = 2, numerical = 3 };

// Builds the simulation the scene needs (a water scene runs no DEM or coupling code, a
// bead scene no fluid code) and runs it.
template <int D, class Kernel>
int dispatch_medium(const dvisph::Scene& s, const dvisph::RunOptions& opt) {
  using namespace dvisph;
  if (s.coupling) {
    Simulation<D, Kernel, PorousMedium<D, Kokkos::DefaultExecutionSpace>> sim(s);
    return run(sim, s, opt);
  }
  Simulation<D, Kernel, ClearWater> sim(s);
  return run(sim, s, opt);
}
template <int D>
int dispatch(const dvisph::Scene& s, const dvisph::RunOptions& opt) {
  using namespace dvisph;
  if (!s.fluid.empty() && s.kernel == "cubic_spline") return dispatch_medium<D, CubicSpline<D>>(s, opt);
  return dispatch_medium<D, WendlandC2<D>>(s, opt);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"dvisph: selective dual-velocity ISPH for solid-liquid flows"};
  app.require_subcommand(1);
  std::string scene_path, out_dir;
  std::vector<std::string> overrides;
  bool quiet = false;

  auto* run = app.add_subcommand("run", "run a scene");
  run->add_option("scene", scene_path, "scene file (YAML)")->required();
  run->add_option("--out", out_dir, "output directory (default: out/<scene name>)");
  run->add_option("--set", overrides, "override a scene key: key.path=value")->take_all();
  run->add_flag("--quiet", quiet, "no progress line");
  std::string restart;
  run->add_option("--restart", restart,
                  "continue from a checkpoint (checkpoint.h5 or last_good.h5 of an earlier run "
                  "of the same scene); output goes to the checkpoint's directory unless --out");
  auto* check = app.add_subcommand("check", "validate a scene file and exit");
  check->add_option("scene", scene_path, "scene file (YAML)")->required();
  check->add_option("--set", overrides, "override a scene key: key.path=value")->take_all();
  app.add_subcommand("schema", "print the scene reference (docs/scenes.md)");

  // Kokkos options (--kokkos-...) are left for Kokkos
  std::vector<std::string> kokkos_args{argv[0]}, own_args;
  for (int i = 1; i < argc; ++i)
    (std::string(argv[i]).rfind("--kokkos", 0) == 0 ? kokkos_args : own_args).push_back(argv[i]);
  try {
    std::reverse(own_args.begin(), own_args.end());
    app.parse(own_args);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? ok : bad_input;
  }

  if (app.got_subcommand("schema")) {
    fmt::print("{}", dvisph::schema_markdown());
    return ok;
  }
  dvisph::Scene scene;
  const bool check_only = app.got_subcommand("check");
  try {
    scene = dvisph::load_scene(scene_path, overrides);
    // a run reads the bed as it starts; a check has to read it here
    if (check_only && scene.solids && !scene.solids->bed.empty()) dvisph::read_bed(scene);
  } catch (const dvisph::SceneError& e) {
    fmt::print(stderr, "error: {}: {}\n", scene_path, e.what());
    return bad_input;
  } catch (const std::exception& e) {  // not the scene's fault (out of memory, a loader bug)
    fmt::print(stderr, "error: {}: cannot load the scene: {}\n", scene_path, e.what());
    return failure;
  }
  for (const auto& w : dvisph::scene_warnings(scene)) fmt::print(stderr, "warning: {}\n", w);
  if (check_only) {
    fmt::print("{}: valid ({}D scene '{}')\n", scene_path, scene.dimension, scene.name);
    return ok;
  }

  std::vector<char*> kargv;
  for (auto& a : kokkos_args) kargv.push_back(a.data());
  int kargc = static_cast<int>(kargv.size());
  Kokkos::ScopeGuard kokkos(kargc, kargv.data());
  if (out_dir.empty())
    out_dir = restart.empty() ? "out/" + scene.name
                              : std::filesystem::path(restart).parent_path().string();
  if (out_dir.empty()) out_dir = ".";
  const dvisph::RunOptions opt{out_dir, !quiet && isatty(fileno(stderr)), restart};
  try {
    return scene.dimension == 2 ? dispatch<2>(scene, opt) : dispatch<3>(scene, opt);
  } catch (const dvisph::SceneError& e) {
    fmt::print(stderr, "error: {}: {}\n", scene_path, e.what());
    return bad_input;
  } catch (const dvisph::NumericalError& e) {
    fmt::print(stderr, "\nnumerical failure: {}\n", e.what());
    return numerical;
  } catch (const std::exception& e) {
    fmt::print(stderr, "\nerror: {}\n", e.what());
    return failure;
  }
}
