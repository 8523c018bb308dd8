// Runs one strategy on one scene and request: prepare -> warm-up -> repetitions of evaluate ->
// read back -> compare with the reference at the requested (u, v) (at the result's own (u, v) for a
// strategy that chooses its samples; `points` is then the number it produced). Whatever happens
// (unavailable, refused, a throw) comes back as a Record; the caller's run goes on.
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "harness/record.h"
#include "reference/reference_evaluator.h"
#include "strategies/registry.h"

namespace nurbs {

// Reference results per (scene, sampling, normals), computed once and shared by every strategy.
class ReferenceCache {
 public:
  explicit ReferenceCache(ReferencePrecision precision = ReferencePrecision::long_double)
      : precision_(precision) {}
  const std::vector<ReferenceSurface>& get(const Scene& scene, const EvalRequest& request);
  ReferencePrecision precision() const { return precision_; }

 private:
  ReferencePrecision precision_;
  std::map<std::string, std::vector<ReferenceSurface>> cache_;
};

// On a trimmed scene, a strategy that trims has its classify() timed after each evaluate() as
// extra phase "classify" (part of end_to_end, and of each frame of measure_deforming), and its
// classification scored with the boundary band `trim_band` (metrics.h TrimScoring).
// `images` (run --images DIR; empty: none): the picture of a strategy that drew
// (Strategy::last_render after the timed render()s) and, for a strategy that classified a trimmed
// scene on a grid, its trim masks (error_image.h names the files).
Record measure(const StrategyEntry& entry, const StrategyOptions& options, const Scene& scene,
               const EvalRequest& request, int repetitions, ReferenceCache& references,
               double trim_band = kDefaultTrimBand, const std::filesystem::path& images = {});

// The deforming-surface benchmark (003 §2): setup prepares frame 0 of deformed_scene(scene, f)
// (scenes/deforming.h); then for f = 1..frames the scene is deformed (not timed: the application
// moving points) and update_control_points() -> evaluate() -> read_back() is timed as one frame.
// A strategy whose capabilities do not say updates_control_points gets prepare() instead, inside
// the frame. extra_phases: "frame" (the whole frame), "frame_update" or "frame_prepare";
// upload / evaluate / read_back hold the frame's parts and end_to_end the frame;
// figures["frames"] = frames. Accuracy: the last frame against the reference of that frame's
// scene (not cached: every frame is a new scene).
Record measure_deforming(const StrategyEntry& entry, const StrategyOptions& options,
                         const Scene& scene, const EvalRequest& request, int frames,
                         ReferencePrecision reference_precision,
                         double trim_band = kDefaultTrimBand);

// The two halves of measure() and measure_deforming(), apart so that process isolation
// (harness/isolation.h) runs the strategy's half in a child and scores in the parent, which keeps
// the reference once per scene x sampling. measure() calls both in one process.
//
// The record measure() starts from: what, where, how many samples; status ok.
Record measurement_record(const StrategyEntry& entry, const Scene& scene,
                          const EvalRequest& request, int repetitions, int deforming_frames);
// A request the strategy refuses for the scene's kind (a T-spline scene met by a NURBS strategy or
// the reverse): fills r (refused, the reason) and returns true. Nothing is probed or started, so
// the isolated run says it without a child process: a quarter of the main job's records.
bool refused_by_kind(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
                     Record& r);
// The strategy's half: availability, refusal, setup, warm-up, repetitions (or frames), read back,
// timings into r. Returns the last read back when there is something to score; nullopt when r is
// already final (unavailable, refused, failed, timed_out). Writes the picture into `images`: the
// strategy's process is the one that holds it.
std::optional<EvalResult> time_measurement(const StrategyEntry& entry,
                                           const StrategyOptions& options, const Scene& scene,
                                           const EvalRequest& request, int repetitions, Record& r,
                                           const std::filesystem::path& images = {});
std::optional<EvalResult> time_deforming(const StrategyEntry& entry, const StrategyOptions& options,
                                         const Scene& scene, const EvalRequest& request, int frames,
                                         Record& r);
// The harness's half: accuracy against the reference (normals oriented first, trims scored with
// `trim_band`), throughput, status; the trim masks into `images` (they need the reference).
void score_measurement(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
                       EvalResult& result, ReferenceCache& references, double trim_band, Record& r,
                       const std::filesystem::path& images = {});
// Against the reference of frame `frames` of the deforming scene.
void score_deforming(const StrategyEntry& entry, const Scene& scene, const EvalRequest& request,
                     int frames, EvalResult& result, ReferencePrecision reference_precision,
                     double trim_band, Record& r);

}  // namespace nurbs
