#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iostream>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "harness/error_image.h"
#include "harness/isolation.h"
#include "harness/metrics.h"
#include "harness/plugins/plugin.h"
#include "harness/runner.h"
#include "harness/strategy_guard.h"
#include "harness/uv_file.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs::cli {

namespace {

Sampling single_sampling(const std::vector<Sampling>& list, std::string_view option) {
  if (list.size() != 1)
    throw InputError(fmt::format("{}: eval takes one sampling, got {} (lists are for run)", option,
                                 list.size()));
  return list.front();
}

template <typename T>
std::string coordinate_text(T x) {
  return fmt::format("{}", x);  // shortest round-trip at the precision it was computed in
}

std::string point_text(const PointArray& a, std::size_t k) {
  if (a.precision() == Precision::f32)
    return fmt::format("{},{},{}", coordinate_text(a.f32()[3 * k]),
                       coordinate_text(a.f32()[3 * k + 1]), coordinate_text(a.f32()[3 * k + 2]));
  return fmt::format("{},{},{}", coordinate_text(a.f64()[3 * k]),
                     coordinate_text(a.f64()[3 * k + 1]), coordinate_text(a.f64()[3 * k + 2]));
}

// The trim figures in words: the errors above are over the inside samples only.
std::string trim_summary(const TrimAccuracy& t) {
  std::string text =
      t.inside == 0
          ? std::string("no sample lies inside the trimmed faces: the errors above are over none")
          : fmt::format("errors over the {} samples inside the faces", t.inside);
  text +=
      fmt::format(", {} boundary samples (band {:g} of the domain diagonal)", t.boundary, t.band);
  if (t.misclassified)
    text += fmt::format(", {} misclassified outside the band (rate {:.3g})", *t.misclassified,
                        t.misclassified_rate.value_or(0));
  else
    text += ", untrimmed (the strategy does not classify)";
  return text;
}

// eval's exit codes beyond main's (0 ok, 2 bad input, 3 internal error): the strategy's verdict,
// 1 -- it produced no points (failed, refused while running, crashed, timed out, out of memory) or
// points that are not all finite (written, to be looked at).
constexpr int kExitStrategyVerdict = 1;

// Under --isolation none the strategy runs in this process: what it prints goes to stderr, so the
// CSV on stdout stays the points alone.
class StdoutToStderr {
 public:
  StdoutToStderr() {
    std::cout.flush();
    std::fflush(stdout);
    saved_ = ::dup(STDOUT_FILENO);
    if (saved_ >= 0) ::dup2(STDERR_FILENO, STDOUT_FILENO);
  }
  ~StdoutToStderr() {
    std::fflush(stdout);
    if (saved_ < 0) return;
    ::dup2(saved_, STDOUT_FILENO);
    ::close(saved_);
  }
  StdoutToStderr(const StdoutToStderr&) = delete;
  StdoutToStderr& operator=(const StdoutToStderr&) = delete;

 private:
  int saved_ = -1;
};

}  // namespace

int eval_command(const EvalOptions& options) {
  const IsolationSettings isolation = isolation_settings(options.isolation);
  apply_thread_setting(options.threads);
  // Before any code of a plugin runs: the file it names (absolute, so a strategy's chdir() cannot
  // move it) can be written.
  const bool to_stdout = options.out.empty() || options.out == "-";
  const std::string out = to_stdout ? "" : writable_output_file("--out", options.out);
  const StrategyOptions strategy_options{
      options.threads, backend_extra(options.gl, options.device, options.strategy_options)};
  load_plugins(options.plugins, isolation);
  const Scene scene = load_scene(options.scene);
  const StrategyEntry* entry = find_strategy(options.strategy);
  if (!entry)
    throw InputError(fmt::format("--strategy = '{}': unknown strategy (known: {})",
                                 options.strategy, fmt::join(strategy_names(), ", ")));
  const ReferencePrecision reference_precision = parse_reference(options.reference);
  const double trim_band = parse_trim_band(options.trim_band);

  EvalRequest request;
  request.precision = parse_precision(options.precision);
  request.normals = options.normals;
  if (!options.uv_file.empty())
    request.sampling = read_uv_file(options.uv_file, scene);
  else
    request.sampling =
        single_sampling(options.span_given ? parse_span_list("--span-samples", options.span_samples)
                                           : parse_grid_list("--samples", options.samples),
                        options.span_given ? "--span-samples" : "--samples");
  const std::vector<SurfaceSamples> samples =
      sample_parameters(scene, request.sampling);  // size checks first
  if (!options.error_image.empty()) {
    error_image_format(options.error_image);
    if (request.sampling.mode == SamplingMode::explicit_list)
      throw InputError(fmt::format(
          "--error-image = {}: needs a grid (--samples) or span grid (--span-samples); an "
          "explicit (u,v) list (--uv) has no image layout",
          options.error_image));
  }

  // A plugin that cannot be used is the strategy's verdict below, like its other failures.
  if (!plugin_problem(*entry)) {
    const Availability availability = entry->probe();
    if (!availability.available)
      throw InputError(
          fmt::format("strategy {} is unavailable: {}", entry->name, availability.reason));
    if (auto refused = refusal_reason(entry->capabilities(), scene, request))
      throw InputError(
          fmt::format("strategy {} refuses scene {}: {}", entry->name, scene.name, *refused));
  }

  // In a child process like run's measurements (unless --isolation none), guarded like them, so
  // that NURBSBENCH_INJECT_FAULT reaches eval too; the points come back to this process, which
  // writes them.
  MeasurementSpec spec{entry, strategy_options, request, 1, 0, trim_band, {}};
  spec.eval_only = true;
  EvalOutcome outcome;
  if (isolation.mode == IsolationMode::none) {
    const StdoutToStderr quiet;
    outcome = evaluate_with(isolation, spec, scene);
  } else {
    outcome = evaluate_with(isolation, spec, scene);
  }
  if (outcome.record.status != Status::ok || !outcome.result) {
    std::cerr << fmt::format("nurbsbench: {} on {}: {}: {}\n", entry->name, scene.name,
                             to_string(outcome.record.status),
                             plugin_text(outcome.record.reason, 2048));
    return kExitStrategyVerdict;
  }
  EvalResult result = std::move(*outcome.result);
  // The strategy's own classification of its samples, for the CSV's inside column.
  const bool classifies = entry->capabilities().trims && scene.has_trims();
  orient_normals(scene, result);  // the CSV and the scoring give the face's normals

  // Compared where the strategy sampled: the request's samples, or its own for a strategy that
  // chooses them (glu-nurbs).
  const std::vector<SurfaceSamples> produced = result_samples(result);
  if (!entry->capabilities().chooses_own_samples && !same_samples(produced, samples))
    throw std::runtime_error(
        fmt::format("strategy {} returned other (u, v) than the requested samples", entry->name));
  const std::vector<ReferenceSurface> reference =
      evaluate_reference(scene, produced, request.normals, reference_precision);
  const Accuracy accuracy =
      measure_accuracy(scene, result, reference, {trim_band, entry->capabilities().trims});
  if (!options.error_image.empty()) {
    const auto paths = write_error_images(
        options.error_image, error_grids(scene, result, reference),
        fmt::format("{} on {}, {} {}, error against the {} reference", entry->name, scene.name,
                    options.precision, request.sampling.label(), options.reference));
    for (const auto& path : paths) std::cerr << "error image: " << path.string() << "\n";
  }
  std::cerr << fmt::format(
      "{} on {} ({}, {}, {} samples): max_abs {:.3g}, rms_abs {:.3g}, max_rel {:.3g}, max_ulp "
      "{:.3g}{} "
      "against the {} reference{}\n",
      entry->name, scene.name, options.precision, request.sampling.label(), total_samples(produced),
      accuracy.max_abs, accuracy.rms_abs, accuracy.max_rel, accuracy.max_ulp,
      accuracy.max_normal_angle_deg
          ? fmt::format(", normals within {:.3g} deg", *accuracy.max_normal_angle_deg)
          : "",
      options.reference, accuracy.trim ? "; " + trim_summary(*accuracy.trim) : "");

  std::string csv = options.normals ? "surface,u,v,x,y,z,nx,ny,nz" : "surface,u,v,x,y,z";
  csv += classifies ? ",inside\n" : "\n";
  for (std::size_t i = 0; i < result.surfaces.size(); ++i) {
    const SurfaceResult& r = result.surfaces[i];
    for (std::size_t k = 0; k < r.positions.size(); ++k) {
      csv += fmt::format("{},{:.17g},{:.17g},{}", i, r.samples.u_of(k), r.samples.v_of(k),
                         point_text(r.positions, k));
      if (options.normals) {
        csv += ',';
        csv += point_text(r.normals, k);
      }
      // An untrimmed surface of a trimmed scene is its whole face.
      if (classifies) csv += r.inside.empty() || r.inside[k] != 0 ? ",1" : ",0";
      csv += "\n";
    }
  }
  if (to_stdout) {
    std::cout << csv << std::flush;
    if (!std::cout) throw InputError("--out = '-': cannot write the points to stdout");
  } else {
    try {
      write_file_atomically(out, csv);
    } catch (const std::runtime_error& e) {
      // It was writable a moment ago: the disk filled or the folder went away.
      throw InputError(fmt::format("--out = '{}': {}", plugin_text(options.out, 256), e.what()));
    }
  }
  // The points are written (they are what to look at), but the evaluation failed.
  const std::string non_finite = non_finite_failure(accuracy, total_samples(produced));
  if (!non_finite.empty()) {
    std::cerr << fmt::format("nurbsbench: {} on {}: {}\n", entry->name, scene.name, non_finite);
    return kExitStrategyVerdict;
  }
  return 0;
}

}  // namespace nurbs::cli
