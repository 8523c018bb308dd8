#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.h"
#include "harness/copy_limit.h"
#include "harness/error_image.h"
#include "harness/gates.h"
#include "harness/link_limit.h"
#include "harness/machine.h"
#include "harness/plugins/plugin.h"
#include "harness/progress.h"
#include "harness/results_writer.h"
#include "harness/runner.h"
#include "harness/store_limit.h"
#include "harness/strategy_guard.h"
#include "harness/summary_table.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/device_wait.h"
#include "strategies/registry.h"

namespace nurbs {
namespace embedded {
extern const std::string_view gates_json;  // results/gates.json, embedded at build time
}  // namespace embedded

namespace cli {

namespace {

struct StrategySelection {
  std::vector<const StrategyEntry*> entries;
  bool store_limit = false;          // the limit-store-bandwidth row (harness/store_limit.h)
  bool device_copy_limit = false;    // the limit-device-copy row (harness/copy_limit.h)
  std::vector<LinkApi> link_limits;  // the limit-link-<api> rows (harness/link_limit.h)
  bool fragment_pass_limit = false;  // limit-gl-fragment-pass (harness/link_limit.h)
  bool any_limit() const {
    return store_limit || device_copy_limit || !link_limits.empty() || fragment_pass_limit;
  }
};

// Every limit row's name, for --strategies' error.
std::vector<std::string> limit_names() {
  std::vector<std::string> names{std::string(kStoreLimitName), std::string(kDeviceCopyLimitName)};
  for (const LinkApi api : kLinkApis) names.push_back(link_limit_name(api));
  names.emplace_back(kFragmentPassLimitName);
  return names;
}

// "all": every registered strategy and every limit row.
StrategySelection strategy_list(const std::string& text) {
  StrategySelection out;
  if (text == "all") {
    out.entries = all_strategies();
    out.store_limit = true;
    out.device_copy_limit = true;
    out.link_limits.assign(std::begin(kLinkApis), std::end(kLinkApis));
    out.fragment_pass_limit = true;
    return out;
  }
  for (const std::string& name : split_list(text)) {
    if (name == kStoreLimitName) {
      out.store_limit = true;
      continue;
    }
    if (name == kDeviceCopyLimitName) {
      out.device_copy_limit = true;
      continue;
    }
    if (name == kFragmentPassLimitName) {
      out.fragment_pass_limit = true;
      continue;
    }
    if (const std::optional<LinkApi> api = link_limit_api(name)) {
      if (std::find(out.link_limits.begin(), out.link_limits.end(), *api) == out.link_limits.end())
        out.link_limits.push_back(*api);
      continue;
    }
    const StrategyEntry* e = find_strategy(name);
    if (!e)
      throw InputError(fmt::format("--strategies: '{}' is not a strategy (known: {}, {})", name,
                                   fmt::join(strategy_names(), ", "),
                                   fmt::join(limit_names(), ", ")));
    out.entries.push_back(e);
  }
  if (out.entries.empty() && !out.any_limit()) throw InputError("--strategies: empty list");
  return out;
}

}  // namespace

IsolationSettings isolation_settings(const IsolationOptions& options) {
  IsolationSettings settings;
  settings.mode = parse_isolation(options.isolation);
  // !(x > 0) also refuses NaN.
  if (!(options.timeout_s > 0) || options.timeout_s > 1e6)
    throw InputError(fmt::format("--timeout = {}: must be in (0, 1e6] seconds", options.timeout_s));
  if (!(options.device_timeout_s > 0) || options.device_timeout_s > 1e6)
    throw InputError(fmt::format("--device-timeout = {}: must be in (0, 1e6] seconds",
                                 options.device_timeout_s));
  settings.timeout_s = options.timeout_s;
  if (!options.memory_limit.empty())
    settings.memory_limit_bytes = parse_memory_limit(options.memory_limit);
  device_wait_limit_s() = options.device_timeout_s;
  // A malformed test fault is bad input here, not a silent fault-free run.
  injected_fault();
  return settings;
}

int run_command(const RunOptions& options) {
  // Everything the run needs is checked before the output directory is touched.
  const IsolationSettings isolation = isolation_settings(options.isolation);
  const int threads = apply_thread_setting(options.threads);
  if (options.repetitions < 1 || options.repetitions > 1000)
    throw InputError(fmt::format("--repetitions = {}: must be in 1..1000", options.repetitions));
  if (options.deforming < 0 || options.deforming > 100000)
    throw InputError(
        fmt::format("--deforming = {}: must be in 1..100000 (frames)", options.deforming));
  const bool deforming = options.deforming > 0;
  // After the checks that cost nothing (a plugin's probe can take up to --timeout), before the
  // strategy list, which may name the plugins.
  load_plugins(options.plugins, isolation);
  const StrategySelection selection = strategy_list(options.strategies);
  const std::vector<const StrategyEntry*>& strategies = selection.entries;
  std::vector<Scene> scenes;
  for (const std::string& name : scene_list(options.scenes)) scenes.push_back(load_scene(name));
  if (scenes.empty()) throw InputError("--scenes: empty list");
  std::vector<Sampling> samplings;
  if (options.samples_given || !options.span_given)
    samplings = parse_grid_list("--samples", options.samples);
  if (options.span_given)
    for (Sampling& s : parse_span_list("--span-samples", options.span_samples))
      samplings.push_back(std::move(s));
  const Precision precision = parse_precision(options.precision);
  const ReferencePrecision reference_precision = parse_reference(options.reference);
  const double trim_band = parse_trim_band(options.trim_band);
  for (const Scene& scene : scenes)
    for (const Sampling& sampling : samplings) sample_parameters(scene, sampling);
  const StrategyOptions strategy_options{
      threads, backend_extra(options.gl, options.device, options.strategy_options)};
  if (!options.images.empty()) {
    if (deforming)
      throw InputError(
          fmt::format("--images = {}: not with --deforming (pictures are of single measurements)",
                      options.images));
    prepare_image_directory("--images", options.images);
  }

  nlohmann::json settings = {{"scenes", nlohmann::json::array()},
                             {"strategies", nlohmann::json::array()},
                             {"samplings", nlohmann::json::array()},
                             {"precision", options.precision},
                             {"normals", options.normals},
                             {"repetitions", options.repetitions},
                             {"deforming_frames", options.deforming},
                             {"threads", threads},
                             {"gl", options.gl.empty() ? "egl" : options.gl},
                             {"strategy_options", options.strategy_options},
                             {"reference", std::string(to_string(reference_precision))},
                             {"trim_band", trim_band},
                             {"isolation", to_string(isolation.mode)},
                             {"timeout_s", isolation.timeout_s},
                             {"memory_limit_mib", isolation.memory_limit_bytes >> 20},
                             {"device_timeout_s", device_wait_limit_s()}};
  for (const Scene& s : scenes) settings["scenes"].push_back(s.name);
  for (const StrategyEntry* e : strategies) settings["strategies"].push_back(e->name);
  if (selection.store_limit) settings["strategies"].push_back(kStoreLimitName);
  if (selection.device_copy_limit) settings["strategies"].push_back(kDeviceCopyLimitName);
  for (const LinkApi api : selection.link_limits)
    settings["strategies"].push_back(link_limit_name(api));
  if (selection.fragment_pass_limit) settings["strategies"].push_back(kFragmentPassLimitName);
  for (const Sampling& s : samplings) settings["samplings"].push_back(s.label());
  ResultsWriter writer(options.out, machine_record(threads), settings);
  // The limit-device-copy rows' device, opened on the first and kept for the others.
  DeviceCopy device_copy(strategy_options);
  // The limit-link-<api> rows' devices, likewise.
  std::vector<std::unique_ptr<LinkCopy>> links;
  for (const LinkApi api : selection.link_limits)
    links.push_back(std::make_unique<LinkCopy>(api, strategy_options));
  // The fragment pass runs on the GL link's context (one GL context for both rows).
  LinkCopy* gl_link = nullptr;
  std::unique_ptr<LinkCopy> gl_link_alone;
  if (selection.fragment_pass_limit) {
    for (const std::unique_ptr<LinkCopy>& link : links)
      if (link->api() == LinkApi::gl) gl_link = link.get();
    if (!gl_link) {
      gl_link_alone = std::make_unique<LinkCopy>(LinkApi::gl, strategy_options);
      gl_link = gl_link_alone.get();
    }
  }

  RunProgress progress(std::cerr, scenes.size() * samplings.size() * strategies.size(),
                       ::isatty(STDERR_FILENO));
  ReferenceCache references(reference_precision);
  for (const Scene& scene : scenes)
    for (const Sampling& sampling : samplings) {
      // The machine's ceiling for this request, measured in the same run as the strategies so
      // their ratios to it are comparable.
      // Not in the deforming benchmark: the limit is an evaluate-only ceiling, not a frame's.
      const EvalRequest limit_request{sampling, precision, options.normals};
      if (selection.store_limit && !deforming)
        writer.append(measure_store_limit(scene, limit_request, options.repetitions));
      // In this process, as `list` enumerates the devices: a copy runs no strategy code.
      if (selection.device_copy_limit && !deforming)
        writer.append(
            measure_device_copy_limit(scene, limit_request, options.repetitions, device_copy));
      // The link rows are about transfers, which a deforming frame has too (the update and the
      // read-back), so they are measured there as well.
      for (const std::unique_ptr<LinkCopy>& link : links)
        writer.append(measure_link_limit(scene, limit_request, options.repetitions, *link));
      if (gl_link && !deforming)
        writer.append(
            measure_fragment_pass_limit(scene, limit_request, options.repetitions, *gl_link));
      for (const StrategyEntry* entry : strategies) {
        progress.start(fmt::format("{} on {} ({})", entry->name, scene.name, sampling.label()));
        EvalRequest request{sampling, precision, options.normals};
        writer.append(measure_with(isolation,
                                   {entry, strategy_options, request, options.repetitions,
                                    options.deforming, trim_band, options.images},
                                   scene, references));
      }
    }
  progress.finish();
  // A T-spline strategy on a NURBS scene (or the reverse) is refused by design; hundreds of such
  // rows hide the measurements. The results files keep every record.
  std::vector<Record> shown;
  for (const Record& r : writer.records())
    if (!(r.status == Status::refused && is_kind_refusal(r.reason))) shown.push_back(r);
  std::cout << summary_table(shown);
  if (shown.size() < writer.records().size())
    std::cout << fmt::format(
        "({} records refused by kind -- a T-spline strategy on a NURBS scene or the reverse -- "
        "are not shown; the results files keep them)\n",
        writer.records().size() - shown.size());
  std::cout << status_counts(writer.records());
  if (deforming)
    std::cout << "\ndeforming, " << options.deforming << " frames:\n"
              << deforming_table(writer.records());
  std::cout << fmt::format(
      "\n{} results in {}/results.json and results.csv (CPU: {}, {} threads; commit {})\n",
      writer.records().size(), options.out, cpu_model(), threads, build_info().git_commit);
  // Last, where a reader of a long table looks first.
  const std::vector<Gate> gates =
      parse_gates(embedded::gates_json, "results/gates.json (built in)");
  std::cout << "\n"
            << fmt::format("{}\n", fmt::join(summary_digest(writer.records(), gates), "\n"));
  return 0;
}

}  // namespace cli
}  // namespace nurbs
