#include "harness/runner.h"

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <map>
#include <stdexcept>

#include "harness/error_image.h"
#include "harness/strategy_guard.h"
#include "scenes/deforming.h"
#include "strategies/device_wait.h"

namespace nurbs {

const std::vector<ReferenceSurface>& ReferenceCache::get(const Scene& scene,
                                                         const EvalRequest& request) {
  // Explicit lists differ per call; never cache them under a shared key.
  const std::string key =
      fmt::format("{}|{}|{}", scene.name, request.sampling.label(), request.normals);
  if (request.sampling.mode == SamplingMode::explicit_list) cache_.erase(key);
  auto it = cache_.find(key);
  if (it == cache_.end())
    it = cache_
             .emplace(key, evaluate_reference(scene, sample_parameters(scene, request.sampling),
                                              request.normals, precision_))
             .first;
  return it->second;
}

bool refused_by_kind(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
                     Record& r) {
  const auto refused = refusal_reason(entry.capabilities(), scene, request);
  if (!refused || !is_kind_refusal(*refused)) return false;
  r.status = Status::refused;
  r.reason = *refused;
  return true;
}

namespace {

Record skeleton(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
                const std::vector<SurfaceSamples>& samples) {
  Record r;
  r.scene = scene.name;
  r.strategy = entry.name;
  r.role = entry.role;
  if (const StrategyLibrary* library = strategy_library(entry)) {
    r.library = library->path;
    r.library_sha256 = library->sha256;
  }
  r.precision = std::string(to_string(request.precision));
  r.sampling = sampling_mode_name(request.sampling.mode);
  r.samples = request.sampling.label();
  r.points = total_samples(samples);
  r.surfaces = scene.surfaces.size();
  r.trimming = trimming_of(entry.capabilities(), scene);
  return r;
}

// Unavailable and refused strategies are results, not runs: fills r and returns false. The
// scene's kind first: refused by design on every machine, so the same record whether or not this
// one can run the strategy (and the isolated run says it without a child, refused_by_kind).
bool runnable(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
              Record& r) {
  // Asked once: the rule scans every control point for the precision's range.
  const std::optional<std::string> refused = refusal_reason(entry.capabilities(), scene, request);
  const auto refuse = [&] {
    r.status = Status::refused;
    r.reason = *refused;
    return false;
  };
  if (refused && is_kind_refusal(*refused)) return refuse();
  const Availability availability = entry.probe();
  if (!availability.available) {
    r.status = Status::unavailable;
    r.reason = availability.reason;
    return false;
  }
  if (refused) return refuse();
  return true;
}

// Compares the result with the reference where the strategy sampled: the requested samples, or
// (a tessellator given a density) its own, whose count then becomes the record's points. The
// reference at the requested samples comes from `references` when the caller has a cache for
// this scene (and is computed only if the strategy sampled there). Orients the result's normals
// (reversed faces).
void score(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
           const std::vector<SurfaceSamples>& requested, EvalResult& result,
           ReferenceCache* references, ReferencePrecision reference_precision, double trim_band,
           Record& r, const std::filesystem::path& images = {}) {
  const std::vector<SurfaceSamples> produced = result_samples(result);
  const bool as_requested = same_samples(produced, requested);
  if (!as_requested) {
    if (!entry.capabilities().chooses_own_samples)
      throw std::runtime_error("result carries other (u, v) than the requested samples");
    r.points = total_samples(produced);
  }
  orient_normals(scene, result);
  const TrimScoring trim{trim_band, entry.capabilities().trims};
  std::vector<ReferenceSurface> own_reference;
  const std::vector<ReferenceSurface>& reference =
      as_requested && references != nullptr
          ? references->get(scene, request)
          : (own_reference =
                 evaluate_reference(scene, produced, request.normals, reference_precision));
  r.accuracy = measure_accuracy(scene, result, reference, trim);
  if (!images.empty() && trim.strategy_trims && scene.has_trims())
    write_trim_masks(images, entry.name, scene, trim_masks(scene, result, reference, trim_band));
  r.throughput_pts_per_s =
      r.evaluate.median_s > 0 ? static_cast<double>(r.points) / r.evaluate.median_s : 0;
  // A NaN anywhere is a wrong answer, not a measurement: outside the face or in the trim band no
  // error figure sees it, yet a renderer or mesher downstream would.
  const std::string non_finite = non_finite_failure(*r.accuracy, r.points);
  r.status = non_finite.empty() ? Status::ok : Status::failed;
  r.reason = non_finite;
}

// A strategy that trims classifies its samples after each evaluation of a trimmed scene; the
// seconds it took, or nothing when it does not (or did not: classify() returned false).
std::optional<double> time_classify(const StrategyEntry& entry, const Scene& scene,
                                    Strategy& strategy) {
  if (!entry.capabilities().trims || !scene.has_trims()) return std::nullopt;
  bool classified = false;
  const double seconds = time_seconds([&] { classified = strategy.classify(); });
  return classified ? std::optional<double>(seconds) : std::nullopt;
}

// The most minor page faults one repetition after the first took in upload and in read_back,
// as figures "upload_page_faults" and "read_back_page_faults": the first may allocate, the others
// should find their buffers in place, so a phase whose median is far above its minimum shows here
// whether the kernel's page faults are the cause.
struct PhaseFaults {
  long upload = 0, read_back = 0;
  bool repeated = false;
  void add(int repetition, long upload_faults, long read_back_faults) {
    if (repetition == 0) return;
    repeated = true;
    upload = std::max(upload, upload_faults);
    read_back = std::max(read_back, read_back_faults);
  }
  void record(Record& r) const {
    if (!repeated) return;
    r.figures["upload_page_faults"] = static_cast<double>(upload);
    r.figures["read_back_page_faults"] = static_cast<double>(read_back);
  }
};

// A strategy that throws is a result too: refused (it said it cannot serve the request) or failed.
template <class Measurement>
void guarded(Record& r, Measurement&& measurement) {
  try {
    measurement();
  } catch (const RefusedError& e) {
    r.status = Status::refused;
    r.reason = e.what();
  } catch (const DeviceTimeout& e) {
    r.status = Status::timed_out;
    r.reason = fmt::format("in {}: {}", current_phase(), e.what());
  } catch (const std::exception& e) {
    r.status = Status::failed;
    r.reason = e.what();
  }
}

}  // namespace

Record measure(const StrategyEntry& entry, const StrategyOptions& options, const Scene& scene,
               const EvalRequest& request, int repetitions, ReferenceCache& references,
               double trim_band, const std::filesystem::path& images) {
  Record r = measurement_record(entry, scene, request, repetitions, 0);
  if (auto result = time_measurement(entry, options, scene, request, repetitions, r, images))
    score_measurement(entry, scene, request, *result, references, trim_band, r, images);
  return r;
}

std::optional<EvalResult> time_measurement(const StrategyEntry& entry,
                                           const StrategyOptions& options, const Scene& scene,
                                           const EvalRequest& request, int repetitions, Record& r,
                                           const std::filesystem::path& images) {
  announce_phase("probe");
  if (!runnable(entry, scene, request, r)) return std::nullopt;
  std::optional<EvalResult> last;
  guarded(r, [&] {
    std::unique_ptr<Strategy> strategy;
    // setup: context, compilation and the first (cold) prepare; paid once.
    r.setup_s = time_seconds([&] {
      strategy = create_guarded(entry, options);
      strategy->prepare(scene, request);
    });
    r.device = strategy->device();
    strategy->evaluate();  // warm-up
    time_classify(entry, scene, *strategy);

    std::vector<double> evaluate_s, device_evaluate_s, classify_s;
    // The device's own clock for the other phases, where the strategy's API has one: each phase's
    // device time after each of its timed calls (DeviceTimes).
    std::map<std::string, std::vector<double>> device_phase_s;
    const auto note_device = [&](const char* phase, std::optional<double> DeviceTimes::*field) {
      if (const std::optional<double> t = strategy->device_times().*field)
        device_phase_s[phase].push_back(*t);
    };
    for (int i = 0; i < repetitions; ++i) {
      evaluate_s.push_back(time_seconds([&] { strategy->evaluate(); }));
      if (auto device = strategy->device_times().evaluate_s) device_evaluate_s.push_back(*device);
      if (auto classify = time_classify(entry, scene, *strategy)) {
        classify_s.push_back(*classify);
        note_device("classify", &DeviceTimes::classify_s);
      }
    }
    if (!classify_s.empty()) r.extra_phases["classify"] = PhaseStats::of(classify_s);
    // Drawing, for strategies that have a render path: one warm-up (shader variants are compiled
    // at the first draw), then the repetitions, each after the evaluation it draws.
    auto time_render = [&](const char* phase, bool (Strategy::*draw)()) {
      if (!(strategy.get()->*draw)()) return;
      std::vector<double> seconds;
      for (int i = 0; i < repetitions; ++i) {
        seconds.push_back(time_seconds([&] { (strategy.get()->*draw)(); }));
        note_device(phase, &DeviceTimes::render_s);
      }
      r.extra_phases[phase] = PhaseStats::of(seconds);
    };
    time_render("render", &Strategy::render);
    // Before render_via_read_back, which draws into the same target.
    if (!images.empty() && r.extra_phases.contains("render"))
      if (std::optional<RenderedImage> picture = strategy->last_render())
        write_render_image(
            render_image_path(images, entry.name, scene.name), *picture,
            fmt::format("{} on {} ({}, {})", entry.name, scene.name, r.precision, r.samples));
    time_render("render_via_read_back", &Strategy::render_via_read_back);
    // The full path, each phase timed where it runs, as a user pays it per update. One result
    // is read back into, repetition after repetition (Strategy::read_back_into), as an
    // application keeps its mesh buffers: a fresh allocation per repetition would time the
    // kernel's page faults, not the copy (issue 30: read_back medians 23x their minima).
    std::vector<double> upload_s, read_back_s, end_to_end_s;
    EvalResult result;
    PhaseFaults faults;
    for (int i = 0; i < repetitions; ++i) {
      const long before_upload = minor_page_faults();
      const double upload = time_seconds([&] { strategy->prepare(scene, request); });
      note_device("upload", &DeviceTimes::upload_s);
      const long after_upload = minor_page_faults();
      const double evaluate = time_seconds([&] { strategy->evaluate(); });
      const double classify = time_classify(entry, scene, *strategy).value_or(0);
      const long before_read_back = minor_page_faults();
      const double read_back = time_seconds([&] { strategy->read_back_into(result); });
      faults.add(i, after_upload - before_upload, minor_page_faults() - before_read_back);
      note_device("read_back", &DeviceTimes::read_back_s);
      upload_s.push_back(upload);
      read_back_s.push_back(read_back);
      end_to_end_s.push_back(upload + evaluate + classify + read_back);
    }
    faults.record(r);
    r.evaluate = PhaseStats::of(evaluate_s);
    r.upload = PhaseStats::of(upload_s);
    r.read_back = PhaseStats::of(read_back_s);
    r.end_to_end = PhaseStats::of(end_to_end_s);
    // Again after the last read-back: details a strategy learns by running (the direct trimming
    // cost counter) belong in the record too; the first read (after setup) stays if a phase fails.
    r.device = strategy->device();
    if (!device_evaluate_s.empty())
      r.device_evaluate_median_s = PhaseStats::of(device_evaluate_s).median_s;
    for (const auto& [phase, seconds] : device_phase_s)
      r.device_phase_median_s[phase] = PhaseStats::of(seconds).median_s;
    last = std::move(result);
  });
  return last;
}

void score_measurement(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
                       EvalResult& result, ReferenceCache& references, double trim_band, Record& r,
                       const std::filesystem::path& images) {
  guarded(r, [&] {
    score(entry, scene, request, sample_parameters(scene, request.sampling), result, &references,
          references.precision(), trim_band, r, images);
  });
}

Record measure_deforming(const StrategyEntry& entry, const StrategyOptions& options,
                         const Scene& scene, const EvalRequest& request, int frames,
                         ReferencePrecision reference_precision, double trim_band) {
  Record r = measurement_record(entry, scene, request, frames, frames);
  if (auto result = time_deforming(entry, options, scene, request, frames, r))
    score_deforming(entry, scene, request, frames, *result, reference_precision, trim_band, r);
  return r;
}

std::optional<EvalResult> time_deforming(const StrategyEntry& entry, const StrategyOptions& options,
                                         const Scene& scene, const EvalRequest& request, int frames,
                                         Record& r) {
  announce_phase("probe");
  if (!runnable(entry, scene, request, r)) return std::nullopt;
  std::optional<EvalResult> last;
  guarded(r, [&] {
    const bool updates = entry.capabilities().updates_control_points;
    Scene frame_scene = deformed_scene(scene, 0);
    std::unique_ptr<Strategy> strategy;
    r.setup_s = time_seconds([&] {
      strategy = create_guarded(entry, options);
      strategy->prepare(frame_scene, request);
    });
    r.device = strategy->device();
    strategy->evaluate();  // warm-up
    time_classify(entry, frame_scene, *strategy);

    std::vector<double> update_s, evaluate_s, classify_s, read_back_s, frame_s;
    EvalResult result;
    for (int f = 1; f <= frames; ++f) {
      deform_scene(scene, f, frame_scene);
      const double update = time_seconds([&] {
        if (updates)
          strategy->update_control_points(frame_scene);
        else
          strategy->prepare(frame_scene, request);
      });
      const double evaluate = time_seconds([&] { strategy->evaluate(); });
      const std::optional<double> classify = time_classify(entry, frame_scene, *strategy);
      const double read_back = time_seconds([&] { strategy->read_back_into(result); });
      update_s.push_back(update);
      evaluate_s.push_back(evaluate);
      if (classify) classify_s.push_back(*classify);
      read_back_s.push_back(read_back);
      frame_s.push_back(update + evaluate + classify.value_or(0) + read_back);
    }
    if (!classify_s.empty()) r.extra_phases["classify"] = PhaseStats::of(classify_s);
    r.upload = PhaseStats::of(update_s);
    r.evaluate = PhaseStats::of(evaluate_s);
    r.read_back = PhaseStats::of(read_back_s);
    r.end_to_end = PhaseStats::of(frame_s);
    r.extra_phases["frame"] = r.end_to_end;
    r.extra_phases[updates ? "frame_update" : "frame_prepare"] = r.upload;
    r.device = strategy->device();  // as time_measurement: what the frames taught the strategy
    last = std::move(result);
  });
  return last;
}

void score_deforming(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
                     int frames, EvalResult& result, ReferencePrecision reference_precision,
                     double trim_band, Record& r) {
  guarded(r, [&] {
    // The reference of the last frame's control points, computed here.
    score(entry, deformed_scene(scene, frames), request, sample_parameters(scene, request.sampling),
          result, nullptr, reference_precision, trim_band, r);
  });
}

Record measurement_record(const StrategyEntry& entry, const Scene& scene,
                          const EvalRequest& request, int repetitions, int deforming_frames) {
  Record r = skeleton(entry, scene, request, sample_parameters(scene, request.sampling));
  r.repetitions = repetitions;
  if (deforming_frames > 0) r.figures["frames"] = deforming_frames;
  return r;
}

}  // namespace nurbs
