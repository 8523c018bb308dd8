#include "harness/recommend.h"

#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.h"
#include "harness/plugins/plugin.h"
#include "harness/results_writer.h"
#include "harness/runner.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs::cli {

namespace {

std::pair<int, int> parse_net(const std::string& text) {
  const std::vector<Sampling> grid = parse_grid_list("--control-net", text);
  if (grid.size() != 1) throw InputError(fmt::format("--control-net = '{}': one NxM", text));
  return {grid.front().grid_u, grid.front().grid_v};
}

// "256x256" (a grid) or "span4" (T steps per knot span): one sampling, as results label them.
Sampling parse_grid_or_span(std::string_view option, const std::string& text) {
  const std::vector<Sampling> list = text.starts_with("span")
                                         ? parse_span_list(option, text.substr(4))
                                         : parse_grid_list(option, text);
  if (list.size() != 1)
    throw InputError(
        fmt::format("{} = '{}': give one sampling (a grid NxM or spanT)", option, text));
  return list.front();
}

// With a results file the workload is one of its scenes; the parameters name the built-in scenes
// made for them (many-N, degree-N, tanN).
std::string scene_for_parameters(const RecommendOptions& o) {
  const int given = (o.degree != -1) + !o.control_net.empty() + (o.surfaces != -1);
  if (given == 0) return "";
  if (given > 1)
    throw InputError(
        "--results with more than one of --degree/--control-net/--surfaces: the workload must be "
        "a measured scene; give --scene (or one parameter: --surfaces N = many-N, --degree N = "
        "degree-N, --control-net NxN = tanN), or drop --results for a quick measurement");
  if (o.surfaces != -1) return fmt::format("many-{}", o.surfaces);
  if (o.degree != -1) return fmt::format("degree-{}", o.degree);
  const auto [cu, cv] = parse_net(o.control_net);
  if (cu != cv)
    throw InputError(
        fmt::format("--control-net = {}: with --results only square nets (tanN scenes) are named",
                    o.control_net));
  return fmt::format("tan{}", cu);
}

// The quick measurement: every registered strategy on the workload, a few repetitions.
std::vector<Record> measure_workload(const RecommendOptions& o, const IsolationSettings& isolation,
                                     const Scene& scene, const Sampling& sampling,
                                     Precision precision) {
  const int threads = apply_thread_setting(o.threads);
  ReferenceCache references;
  std::vector<Record> records;
  for (const StrategyEntry* entry : all_strategies()) {
    std::cerr << fmt::format("measuring {} on {} ({})...\n", entry->name, scene.name,
                             sampling.label());
    records.push_back(measure_with(isolation,
                                   {entry, StrategyOptions{threads, {}},
                                    EvalRequest{sampling, precision, false}, o.repetitions, 0},
                                   scene, references));
  }
  return records;
}

}  // namespace

int recommend_command(const RecommendOptions& o) {
  // Checked first, and bounding the plugins' probes too.
  const IsolationSettings isolation = isolation_settings(o.isolation);
  load_plugins(o.plugins, isolation);
  Workload workload;
  workload.tolerance = parse_tolerance(o.tolerance);
  workload.deforming = o.deforming;
  if (!o.samples.empty()) workload.samples = parse_grid_or_span("--samples", o.samples).label();
  if (!o.precision.empty()) {
    parse_precision(o.precision);
    workload.precision = o.precision;
  }
  if (o.repetitions < 1 || o.repetitions > 1000)
    throw InputError(fmt::format("--repetitions = {}: must be in 1..1000", o.repetitions));

  std::vector<Record> records;
  if (!o.results.empty()) {
    if (!o.scene.empty() && !scene_for_parameters(o).empty())
      throw InputError("--scene and --degree/--control-net/--surfaces: give one workload");
    const std::string scene = o.scene.empty() ? scene_for_parameters(o) : o.scene;
    if (!scene.empty()) workload.scene = scene;
    records = read_results(o.results).records;
  } else {
    if (!o.scene.empty() && (o.degree != -1 || !o.control_net.empty() || o.surfaces != -1))
      throw InputError("--scene and --degree/--control-net/--surfaces: give one workload");
    Scene scene;
    if (!o.scene.empty()) {
      scene = load_scene(o.scene);
    } else {
      const auto [cu, cv] = o.control_net.empty() ? std::pair{12, 12} : parse_net(o.control_net);
      scene =
          workload_scene(o.degree != -1 ? o.degree : 3, cu, cv, o.surfaces != -1 ? o.surfaces : 1);
    }
    const std::string samples = o.samples.empty() ? "64x64" : o.samples;
    const Sampling sampling = parse_grid_or_span("--samples", samples);
    sample_parameters(scene, sampling);  // size checks before measuring
    workload.scene = scene.name;
    workload.samples = sampling.label();
    records = measure_workload(o, isolation, scene, sampling,
                               parse_precision(o.precision.empty() ? "f32" : o.precision));
  }
  const Recommendation r = recommend(records, workload);
  if (o.json)
    std::cout << recommendation_json(r, workload).dump(1) << "\n";
  else
    std::cout << recommendation_text(r, workload);
  return r.ranked.empty() ? 1 : 0;
}

}  // namespace nurbs::cli
