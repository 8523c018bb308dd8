#include <fmt/format.h>
#include <unistd.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.h"
#include "harness/machine.h"
#include "harness/results_writer.h"
#include "harness/runner.h"
#include "harness/summary_table.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs::cli {

namespace {

// "default": every listed built-in scene except those whose default grids exceed the per-request
// sample limit (many-4096); "all": every listed built-in scene.
std::vector<std::string> scene_list(const std::string& text) {
  if (text == "default" || text == "all") {
    std::vector<std::string> names;
    for (const BuiltinSceneInfo& s : builtin_scenes())
      if (text == "all" || s.name != "many-4096") names.push_back(s.name);
    return names;
  }
  return split_list(text);
}

std::vector<const StrategyEntry*> strategy_list(const std::string& text) {
  std::vector<const StrategyEntry*> out;
  if (text == "all") {
    for (const StrategyEntry& e : strategy_registry()) out.push_back(&e);
    return out;
  }
  for (const std::string& name : split_list(text)) {
    const StrategyEntry* e = find_strategy(name);
    if (!e)
      throw InputError(fmt::format("--strategies: '{}' is not a strategy (known: {})", name,
                                   fmt::join(strategy_names(), ", ")));
    out.push_back(e);
  }
  if (out.empty()) throw InputError("--strategies: empty list");
  return out;
}

}  // namespace

int run_command(const RunOptions& options) {
  // Everything the run needs is checked before the output directory is touched.
  const int threads = apply_thread_setting(options.threads);
  if (options.repetitions < 1 || options.repetitions > 1000)
    throw InputError(fmt::format("--repetitions = {}: must be in 1..1000", options.repetitions));
  const std::vector<const StrategyEntry*> strategies = strategy_list(options.strategies);
  std::vector<Scene> scenes;
  for (const std::string& name : scene_list(options.scenes)) scenes.push_back(load_scene(name));
  if (scenes.empty()) throw InputError("--scenes: empty list");
  const std::vector<Sampling> samplings =
      !options.span_given ? parse_grid_list("--samples", options.samples)
                          : parse_span_list("--span-samples", options.span_samples);
  const Precision precision = parse_precision(options.precision);
  const ReferencePrecision reference_precision = parse_reference(options.reference);
  for (const Scene& scene : scenes)
    for (const Sampling& sampling : samplings) sample_parameters(scene, sampling);

  nlohmann::json settings = {{"scenes", nlohmann::json::array()},
                             {"strategies", nlohmann::json::array()},
                             {"samplings", nlohmann::json::array()},
                             {"precision", options.precision},
                             {"normals", options.normals},
                             {"repetitions", options.repetitions},
                             {"threads", threads},
                             {"gl", options.gl.empty() ? "egl" : options.gl},
                             {"strategy_options", options.strategy_options},
                             {"reference", std::string(to_string(reference_precision))}};
  for (const Scene& s : scenes) settings["scenes"].push_back(s.name);
  for (const StrategyEntry* e : strategies) settings["strategies"].push_back(e->name);
  for (const Sampling& s : samplings) settings["samplings"].push_back(s.label());
  ResultsWriter writer(options.out, machine_record(threads), settings);

  const bool progress = ::isatty(STDERR_FILENO);
  const std::size_t total = scenes.size() * samplings.size() * strategies.size();
  std::size_t done = 0;
  ReferenceCache references(reference_precision);
  for (const Scene& scene : scenes)
    for (const Sampling& sampling : samplings)
      for (const StrategyEntry* entry : strategies) {
        if (progress)
          std::cerr << fmt::format("\r[{}/{}] {} on {} ({})\x1b[K", ++done, total, entry->name,
                                   scene.name, sampling.label())
                    << std::flush;
        EvalRequest request{sampling, precision, options.normals};
        writer.append(measure(*entry,
                              StrategyOptions{threads, backend_extra(options.gl, options.device,
                                                                     options.strategy_options)},
                              scene, request, options.repetitions, references));
      }
  if (progress) std::cerr << "\r\x1b[K";
  std::cout << summary_table(writer.records());
  std::cout << fmt::format(
      "\n{} results in {}/results.json and results.csv (CPU: {}, {} threads; commit {})\n",
      writer.records().size(), options.out, cpu_model(), threads, build_info().git_commit);
  return 0;
}

}  // namespace nurbs::cli
