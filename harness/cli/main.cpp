// nurbsbench: evaluate NURBS surfaces with every strategy, check them against the reference, time
// them (see docs/cli.md for every verb).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "harness/cli/commands.h"
#include "harness/drivers.h"
#include "harness/plugins/plugin.h"
#include "reference/validation.h"

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/lsan_interface.h>
#endif

namespace {

// The exit codes every verb shares: 0 ok, 1 a verdict (a gate violated, non-finite output), 2 bad
// input (a command line, a file, a path), 3 an internal error.
constexpr int kExitBadInput = 2;
constexpr int kExitInternalError = 3;

// One line on stderr, whatever the message holds (a plugin's bytes included).
void print_error(const char* kind, const std::string& message) {
  std::cerr << "nurbsbench: " << kind << ": " << nurbs::plugin_text(message, 4096) << "\n";
}

void add_isolation_options(CLI::App* verb, nurbs::cli::IsolationOptions& options) {
  verb->add_option("--isolation", options.isolation,
                   "process (default: each measurement in its own process, so a crash or hang "
                   "costs only its record) or none (in this process, for debugging)")
      ->check(CLI::IsMember({"process", "none"}));
  verb->add_option("--timeout", options.timeout_s,
                   "seconds one measurement may take (setup, warm-up, repetitions) before its "
                   "process group is killed and it is recorded timed_out (default 600)");
  verb->add_option("--device-timeout", options.device_timeout_s,
                   "seconds any single wait on a GL/Vulkan/OpenCL device may take before the "
                   "strategy reports timed_out in that phase (default 60)");
  verb->add_option("--memory-limit", options.memory_limit,
                   "MiB of resident memory one measurement's process may hold before it is "
                   "killed and recorded failed: out of memory (default: 3/4 of this machine's)")
      ->type_name("MIB");
}

void add_plugin_option(CLI::App* verb, std::vector<std::string>& plugins) {
  verb->add_option("--plugin", plugins,
                   "evaluator plugin: a shared library implementing "
                   "include/nurbsbench/evaluator.h, measured as the strategy its table names "
                   "(repeatable)")
      ->type_name("PATH.so");
}

constexpr const char* kTrimBandHelp =
    "trimmed scenes: samples nearer the trim boundary than FRACTION of the surface's (u,v) domain "
    "diagonal are boundary samples, not scored for classification (default 1e-7; recorded)";
}  // namespace

static int run_command_line(int argc, char** argv) {
  using namespace nurbs::cli;
  CLI::App app{
      "nurbsbench: NURBS surface evaluation strategies, benchmarked and checked against a "
      "high-precision reference"};
  app.require_subcommand(1);
  // Given before or after the verb (fallthrough): a driver the loaders do not find by themselves.
  std::vector<std::string> driver_dirs;
  app.add_option("--driver-dir", driver_dirs,
                 "folder of a GPU driver installed where the loaders do not look (its Vulkan "
                 "ICD manifests, EGL vendor files, OpenCL ICDs and libraries); repeatable")
      ->type_name("DIR");
  app.fallthrough();

  ListOptions list;
  auto* list_cmd =
      app.add_subcommand("list", "strategies (available / unavailable: why) and built-in scenes");
  list_cmd->add_flag("--json", list.json, "machine-readable output");
  add_plugin_option(list_cmd, list.plugins);
  list_cmd->add_option("--timeout", list.timeout_s,
                       "seconds each --plugin's probe (load, constructors, entry point) may take "
                       "before it is killed and the plugin is unavailable (default 60)");

  SceneOptions scene;
  auto* scene_cmd = app.add_subcommand("scene",
                                       "write a scene (built-in name or file) as nurbs-scene/1 "
                                       "JSON (/2 when it has trims, reversed faces or T-splines)");
  scene_cmd->add_option("name", scene.scene, "built-in scene name or scene file")->required();
  scene_cmd->add_option("--out", scene.out, "output file (default: stdout)");

  ImportOptions import;
  auto* import_cmd = app.add_subcommand(
      "import",
      "read a CAD model (STEP, IGES, BREP) into a scene of trimmed NURBS surfaces, one per face");
  import_cmd->add_option("model", import.model, "model file: .stp/.step, .igs/.iges or .brep")
      ->required();
  import_cmd->add_option("--out", import.out, "scene file to write (default: stdout)");
  import_cmd->add_flag("--strict", import.strict, "a skipped face is an error (exit 2)");

  EvalOptions eval;
  auto* eval_cmd =
      app.add_subcommand("eval", "evaluate one scene with one strategy, write points as CSV");
  eval_cmd->add_option("--scene", eval.scene, "built-in scene name or scene file")->required();
  eval_cmd->add_option("--strategy", eval.strategy, "strategy name (see `list`)")->required();
  auto* eval_samples =
      eval_cmd->add_option("--samples", eval.samples, "grid NUxNV (default 64x64)");
  auto* eval_span =
      eval_cmd->add_option("--span-samples", eval.span_samples, "T steps per non-empty knot span");
  // An empty name would read as "no --uv" and evaluate the default grid instead: refuse it.
  auto* eval_uv =
      eval_cmd->add_option("--uv", eval.uv_file, "CSV file of surface,u,v samples")
          ->check(CLI::Validator(
              [](std::string& name) {
                return name.empty() ? std::string("the file name is empty") : std::string();
              },
              "FILE"));
  eval_samples->excludes(eval_span)->excludes(eval_uv);
  eval_span->excludes(eval_uv);
  eval_cmd->add_flag("--normals", eval.normals, "also output unit normals");
  add_plugin_option(eval_cmd, eval.plugins);
  eval_cmd->add_option("--precision", eval.precision, "f32 (default) or f64");
  eval_cmd->add_option("--reference", eval.reference, "long-double (default) or float128");
  eval_cmd->add_option("--threads", eval.threads, "threads for every backend (0: every core)");
  eval_cmd
      ->add_option("--gl", eval.gl, "OpenGL platform of the GL strategies: egl (default) or osmesa")
      ->check(CLI::IsMember({"osmesa", "egl"}));
  eval_cmd->add_option("--device", eval.device,
                       "OpenCL device index across all platforms, or Vulkan physical device index "
                       "(default: a GPU if present, else the first)");
  eval_cmd->add_option("--strategy-option", eval.strategy_options,
                       "KEY=VALUE for the strategies that read KEY (repeatable), e.g. "
                       "vk-mode=adaptive, vk-eye=x,y,z, vk-center=x,y,z, vk-mu=4 (vk-ksquad)");
  eval_cmd->add_option("--error-image", eval.error_image,
                       "heat map of the error over (u,v): F.exr (raw float error, model units) or "
                       "F.png (colour map, ulps, legend); several surfaces: F-<index>.ext");
  eval_cmd->add_option("--trim-band", eval.trim_band, kTrimBandHelp)->type_name("FRACTION");
  eval_cmd->add_option("--out", eval.out,
                       "CSV file surface,u,v,x,y,z[,nx,ny,nz][,inside] (inside: a strategy that "
                       "trims, on a trimmed scene; default: stdout)");
  add_isolation_options(eval_cmd, eval.isolation);

  RunOptions run;
  auto* run_cmd = app.add_subcommand(
      "run", "benchmark strategies x scenes x samplings, write results.json/.csv");
  run_cmd->add_option("--scenes", run.scenes,
                      "comma list of scene names/files, 'default' or 'all'");
  run_cmd->add_option("--strategies", run.strategies, "comma list of strategies or 'all'");
  auto* run_samples =
      run_cmd->add_option("--samples", run.samples, "comma list of grids (default 64x64,256x256)");
  auto* run_span =
      run_cmd->add_option("--span-samples", run.span_samples, "comma list of steps per knot span");
  run_cmd->add_option("--precision", run.precision, "f32 (default) or f64");
  run_cmd->add_flag("--normals", run.normals, "also evaluate and check normals");
  run_cmd->add_option("--repetitions", run.repetitions, "timed repetitions per phase (default 5)");
  run_cmd->add_option("--deforming", run.deforming,
                      "deforming-surface benchmark: FRAMES frames of a travelling wave, each "
                      "update_control_points (or prepare) -> evaluate -> read back, timed as "
                      "extra phase 'frame'; accuracy on the last frame");
  run_cmd->add_option("--reference", run.reference, "long-double (default) or float128");
  run_cmd->add_option("--threads", run.threads, "threads for every backend (0: every core)");
  run_cmd
      ->add_option("--gl", run.gl, "OpenGL platform of the GL strategies: egl (default) or osmesa")
      ->check(CLI::IsMember({"osmesa", "egl"}));
  run_cmd->add_option("--device", run.device,
                      "OpenCL device index across all platforms, or Vulkan physical device index "
                      "(default: a GPU if present, else the first)");
  run_cmd->add_option("--strategy-option", run.strategy_options,
                      "KEY=VALUE for the strategies that read KEY (repeatable), e.g. "
                      "vk-mode=adaptive, vk-eye=x,y,z, vk-center=x,y,z, vk-mu=4 (vk-ksquad)");
  run_cmd->add_option("--trim-band", run.trim_band, kTrimBandHelp)->type_name("FRACTION");
  run_cmd->add_option("--out", run.out, "output directory (default results/latest)");
  run_cmd
      ->add_option("--images", run.images,
                   "write DIR/<strategy>__<scene>.png (what a drawing strategy drew) and, for a "
                   "strategy that trims, DIR/<strategy>__<scene>__mask<surface>.png (PNG)")
      ->type_name("DIR");
  add_isolation_options(run_cmd, run.isolation);
  add_plugin_option(run_cmd, run.plugins);

  LodOptions lod;
  auto* lod_cmd = app.add_subcommand(
      "lod", "002 Fig 15: level-of-detail change by Haar wavelet vs re-evaluation (glsl-deboor)");
  lod_cmd->add_option("--scene", lod.scene, "one-surface scene (default tan21x23, the paper's)");
  lod_cmd->add_option("--samples", lod.samples,
                      "comma list of grids (default 128x128,512x512,1024x1024)");
  lod_cmd->add_option("--levels", lod.levels, "coarser levels measured (default 3)");
  lod_cmd->add_option("--repetitions", lod.repetitions, "timed repetitions (default 7)");
  lod_cmd->add_option("--threads", lod.threads, "threads for llvmpipe (0: every core)");
  lod_cmd->add_option("--gl", lod.gl, "OpenGL platform: egl (default) or osmesa")
      ->check(CLI::IsMember({"osmesa", "egl"}));
  lod_cmd->add_option("--out", lod.out, "output directory for lod.json (default results/latest)");
  lod_cmd
      ->add_option("--images", lod.images,
                   "write DIR/lod__<scene>__<samples>__L<level>.png: each level as drawn (PNG)")
      ->type_name("DIR");

  CameraPathOptions camera;
  auto* camera_cmd = app.add_subcommand(
      "camera-path",
      "000 §3.2: continuous LOD along a fly-in (gl-pingpong, drawn from a device copy) vs a fixed "
      "grid re-evaluated every frame");
  camera_cmd->add_option("--scenes", camera.scenes,
                         "comma list of scenes (default teapot: 32 surfaces)");
  camera_cmd->add_option("--frames", camera.frames, "frames of the fly-in (default 60)");
  camera_cmd->add_option("--viewport", camera.viewport, "image size WxH (default 640x480)");
  camera_cmd->add_option("--pixels-per-sample", camera.pixels_per_sample,
                         "projected pixels per evaluated sample (default 4)");
  camera_cmd->add_option("--min-samples", camera.min_samples,
                         "fewest samples per side of a surface (default 4)");
  camera_cmd->add_option("--max-samples", camera.max_samples,
                         "most samples per side of a surface (default 256)");
  camera_cmd->add_option("--fixed-samples", camera.fixed_samples,
                         "the baseline's grid for every surface, WxH (default 64x64)");
  camera_cmd->add_option("--threads", camera.threads, "threads for llvmpipe (0: every core)");
  camera_cmd->add_option("--gl", camera.gl, "OpenGL platform: egl (default) or osmesa")
      ->check(CLI::IsMember({"osmesa", "egl"}));
  camera_cmd->add_option("--out", camera.out,
                         "output directory for camera_path.json (default results/latest)");
  camera_cmd
      ->add_option("--images", camera.images,
                   "write DIR/camera_path__<scene>__<lod|fixed>__f<frame>.png: the first and last "
                   "frames as drawn (PNG)")
      ->type_name("DIR");

  MemoryOptions memory;
  auto* memory_cmd = app.add_subcommand(
      "memory",
      "RPNS Table 1: control points and bytes as NURBS vs after Bezier decomposition, KSQuads");
  memory_cmd->add_option("--scenes", memory.scenes,
                         "comma list of scene names/files, 'default' or 'all'");
  memory_cmd->add_flag("--json", memory.json, "machine-readable output");

  CheckOptions check;
  auto* check_cmd =
      app.add_subcommand("check", "check results against accuracy gates; exit 1 on any violation");
  check_cmd->add_option("--gates", check.gates, "gates JSON file")->required();
  check_cmd->add_option("--results", check.results,
                        "results directory or results.json (default results/latest)");

  ReportOptions report;
  auto* report_cmd = app.add_subcommand(
      "report", "REPORT.md, index.html and the paper charts (PNG) from one or more results sets");
  report_cmd
      ->add_option("--results", report.results,
                   "results directory (repeat for several; lod.json, camera_path.json and "
                   "memory.json beside results.json are read too), or a folder of them "
                   "(results/canonical: every set below it)")
      ->required();
  report_cmd->add_option("--out", report.out, "output directory (default: <first results>/report)");
  report_cmd->add_option("--python", report.python,
                         "Python with matplotlib that draws the charts (default /usr/bin/python3)");
  report_cmd->add_option("--error-images", report.error_images,
                         "error heat maps of the N worst (strategy, scene) pairs, re-evaluated on "
                         "this machine (default 3; 0: none)");
  report_cmd->add_option(
      "--trim-masks", report.trim_masks,
      "trim masks of the N (strategy, trimmed scene) pairs with the most "
      "misclassified samples, re-evaluated on this machine (default 3; 0: none)");

  RecommendOptions recommend;
  auto* recommend_cmd = app.add_subcommand(
      "recommend",
      "strategies ranked by measured throughput among those within a tolerance, for a workload; "
      "exit 1 when none is");
  recommend_cmd
      ->add_option("--tolerance", recommend.tolerance,
                   "max error: '8ulp' (max_ulp) or model units '1e-5' (max_abs)")
      ->required();
  recommend_cmd->add_option("--results", recommend.results,
                            "results directory or results.json (default: measure the workload "
                            "here, quickly)");
  recommend_cmd->add_option("--scene", recommend.scene, "the workload's scene (name or file)");
  recommend_cmd->add_option("--degree", recommend.degree, "workload degree (quick run; default 3)");
  recommend_cmd->add_option("--control-net", recommend.control_net,
                            "workload control net NxM (quick run; default 12x12)");
  recommend_cmd->add_option("--surfaces", recommend.surfaces,
                            "workload surface count (quick run; default 1)");
  recommend_cmd->add_option("--samples", recommend.samples,
                            "grid NxM or spanT (quick run default 64x64)");
  recommend_cmd->add_option("--precision", recommend.precision, "f32 or f64 (default: both / f32)");
  recommend_cmd->add_flag("--deforming", recommend.deforming,
                          "control points change every frame: rank by the frame phase");
  recommend_cmd->add_option("--repetitions", recommend.repetitions,
                            "repetitions of the quick run (default 3)");
  recommend_cmd->add_option("--threads", recommend.threads, "threads of the quick run (0: all)");
  recommend_cmd->add_flag("--json", recommend.json, "machine-readable output");
  add_isolation_options(recommend_cmd, recommend.isolation);
  add_plugin_option(recommend_cmd, recommend.plugins);

  // Hidden (no group): the process that forks isolated measurements, started by run/recommend.
  int measure_server_fd = -1;
  auto* measure_server_cmd = app.add_subcommand("measure-server", "")->group("");
  measure_server_cmd->add_option("fd", measure_server_fd)->required();

  GbenchOptions gbench;
  auto* gbench_cmd = app.add_subcommand(
      "gbench-json", "convert results.json to Google Benchmark JSON (for compare.py)");
  gbench_cmd->add_option("--results", gbench.results,
                         "results directory or results.json (default results/latest)");
  gbench_cmd->add_option("--out", gbench.out, "output file (default: stdout)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    const std::string first = argc > 1 ? argv[1] : "";
    // The verbs are the subcommands registered above: one list, never restated by hand.
    std::vector<std::string> verbs;
    for (const CLI::App* verb : app.get_subcommands({}))
      if (!verb->get_group().empty()) verbs.push_back(verb->get_name());
    const bool known_verb = std::find(verbs.begin(), verbs.end(), first) != verbs.end();
    if (!first.empty() && first[0] != '-' && !known_verb) {
      std::cerr << "nurbsbench: error: unknown verb '" << argv[1]
                << "' (verbs: " << fmt::format("{}", fmt::join(verbs, ", "))
                << "; see nurbsbench --help)\n";
      return 2;
    }
    std::cerr << "nurbsbench: error: " << e.what() << " (see nurbsbench --help)\n";
    return 2;
  }

  eval.span_given = eval_span->count() > 0;
  run.samples_given = run_samples->count() > 0;
  run.span_given = run_span->count() > 0;
  try {
    if (!driver_dirs.empty() && nurbs::apply_driver_dirs(driver_dirs)) nurbs::reexecute(argv);
    if (*list_cmd) return list_command(list);
    if (*scene_cmd) return scene_command(scene);
    if (*import_cmd) return import_command(import);
    if (*eval_cmd) return eval_command(eval);
    if (*run_cmd) return run_command(run);
    if (*lod_cmd) return lod_command(lod);
    if (*camera_cmd) return camera_path_command(camera);
    if (*check_cmd) return check_command(check);
    if (*memory_cmd) return memory_command(memory);
    if (*report_cmd) return report_command(report);
    if (*recommend_cmd) return recommend_command(recommend);
    if (*gbench_cmd) return gbench_command(gbench);
    if (*measure_server_cmd) return nurbs::measure_server(measure_server_fd);
  } catch (const nurbs::InputError& e) {
    print_error("error", e.what());
    return kExitBadInput;
  } catch (const std::filesystem::filesystem_error& e) {
    // A path the user named that cannot be read, created or written: theirs to fix, like bad
    // input.
    print_error("error", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    // Anything else is ours: not "bad input" (exit 2 tells a CI script the command line or a
    // file is wrong), so it says so and exits with its own code.
    print_error("internal error",
                std::string(e.what()) + " (a bug in nurbsbench: please report it)");
    return kExitInternalError;
  }
  return kExitBadInput;
}

int main(int argc, char** argv) {
  const int status = run_command_line(argc, argv);
#if defined(__SANITIZE_ADDRESS__)
  // The leak check of a sanitizer build, done here rather than at exit: during exit the thread
  // pools of loaded libraries (log4cplus, pulled in through OpenImageIO and OpenVDB, starts four
  // threads) are torn down, and a thread caught mid-exit crashed LeakSanitizer's thread walk
  // under load ("Tracer caught signal 11", CI). Here every such thread is parked; the check runs
  // once, so the exit-time one does nothing.
  __lsan_do_leak_check();
#endif
  return status;
}
