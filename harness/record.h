// One measurement: a (scene, strategy, precision, sampling) with its timings, its accuracy and
// its status. The runner emits these; the writers, `check` and later `report` read them.
#pragma once

#include <map>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "harness/metrics.h"
#include "harness/timing.h"
#include "strategies/strategy.h"

namespace nurbs {

// Ordered like the Khronos CTS result codes (docs/design.md §Isolation and result codes): the
// later, the worse for the strategy. out_of_memory, crashed and timed_out come only from an
// isolated measurement (its process held more than --memory-limit, a signal ended it, or the
// watchdog did) or a bounded device wait that expired.
enum class Status { ok, refused, unavailable, failed, out_of_memory, crashed, timed_out };
inline constexpr Status kAllStatuses[] = {
    Status::ok,      Status::refused,  Status::unavailable, Status::failed, Status::out_of_memory,
    Status::crashed, Status::timed_out};
std::string_view to_string(Status s);
bool parse_status(std::string_view text, Status& out);

struct Record {
  std::string scene;
  std::string strategy;
  std::string role;  // strategy / baseline / peer / limit / plugin
  // A plugin's shared library as given to --plugin and the SHA-256 of its bytes (JSON only; the
  // CSV's columns are fixed); empty for built-in strategies.
  std::string library, library_sha256;
  DeviceInfo device;
  std::string precision;  // f32 / f64
  std::string sampling;   // grid / span_grid / explicit
  std::string samples;    // "1024x1024", "span4"
  // Samples compared: the request's, or those a strategy that chooses its own (glu-nurbs) made.
  std::size_t points = 0;
  std::size_t surfaces = 0;
  int repetitions = 0;
  double setup_s = 0;
  PhaseStats upload, evaluate, read_back, end_to_end;
  std::optional<double> device_evaluate_median_s;
  // The device's clock for the other phases a strategy's API times (upload, read_back, classify,
  // render, render_via_read_back): each phase's median over its repetitions, beside the wall
  // clock's in the phase itself. Empty for host strategies.
  std::map<std::string, double> device_phase_median_s;
  // Phases beyond the four every strategy has, where a strategy or mode has them: "render"
  // (drawing without read-back), "render_via_read_back", "frame" (one deforming frame)...
  std::map<std::string, PhaseStats> extra_phases;
  // Named measurements that are not times, e.g. a limit row's "store_bytes_per_s".
  std::map<std::string, double> figures;
  double throughput_pts_per_s = 0;
  // Absent when nothing was evaluated: a record of role "limit" (a machine ceiling measured in
  // the same run, such as the memory store bandwidth) or one that did not run.
  std::optional<Accuracy> accuracy;
  // On a trimmed scene: "classified" (the strategy trims; accuracy->trim has its
  // misclassification) or "untrimmed" (it evaluated the whole surfaces: a label, not a failure);
  // "" on a scene without trims (metrics.h trimming_of).
  std::string trimming;
  Status status = Status::ok;
  std::string reason;
};

nlohmann::json record_to_json(const Record& r);
Record record_from_json(const nlohmann::json& j);

// The CSV of docs/formats.md / the foundation issue: the columns are fixed, in this order; the trim
// columns (trimming, trim_band, trim_inside_samples, trim_boundary_samples, trim_misclassified,
// trim_misclassified_rate) come last, empty where they do not apply, so readers of the first
// columns by position keep working.
std::string csv_header();
std::string csv_row(const Record& r);

}  // namespace nurbs
