#include "harness/summary_table.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <vector>

namespace nurbs {

namespace {

using Row = std::vector<std::string>;

std::string seconds_text(double s) {
  if (s >= 1) return fmt::format("{:.3f} s", s);
  if (s >= 1e-3) return fmt::format("{:.3f} ms", s * 1e3);
  return fmt::format("{:.1f} us", s * 1e6);
}

// Columns padded to their widest cell; the last column is left ragged (it holds reasons).
std::string aligned(const std::vector<Row>& rows) {
  std::vector<std::size_t> width(rows.front().size());
  for (const Row& row : rows)
    for (std::size_t c = 0; c + 1 < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  std::string out;
  for (const Row& row : rows) {
    for (std::size_t c = 0; c < row.size(); ++c)
      out += c + 1 < row.size() ? fmt::format("{:<{}}  ", row[c], width[c]) : row[c];
    out += "\n";
  }
  return out;
}

// Errors over the samples inside the faces: over none, a 0 would read as perfect.
std::string max_ulp_text(const Accuracy& a) {
  if (no_inside_samples(a)) return "- (0 inside)";
  return fmt::format("{:.3g}", a.max_ulp);
}

}  // namespace

std::string trim_text(const Record& r) {
  if (r.trimming != "classified" || r.status != Status::ok || !r.accuracy || !r.accuracy->trim ||
      !r.accuracy->trim->misclassified)
    return r.trimming;
  const TrimAccuracy& t = *r.accuracy->trim;
  return fmt::format("{} misclassified ({:.3g}), {} boundary", *t.misclassified,
                     t.misclassified_rate.value_or(0), t.boundary);
}

std::string summary_table(const std::vector<Record>& records) {
  const bool trims = std::any_of(records.begin(), records.end(),
                                 [](const Record& r) { return !r.trimming.empty(); });
  std::vector<Row> rows = {{"scene", "strategy", "on", "prec", "samples", "evaluate (median)",
                            "points/s", "max_ulp", "status"}};
  if (trims) rows[0].insert(rows[0].end() - 1, "trim");
  for (const Record& r : records) {
    const bool ok = r.status == Status::ok;
    Row row = {r.scene,
               r.strategy,
               r.device.kind.empty() ? "-" : r.device.kind,
               r.precision,
               r.samples,
               ok ? seconds_text(r.evaluate.median_s) : "",
               ok ? fmt::format("{:.3g}", r.throughput_pts_per_s) : "",
               ok && r.accuracy ? max_ulp_text(*r.accuracy) : "",
               ok ? "ok" : fmt::format("{}: {}", to_string(r.status), r.reason)};
    if (trims) row.insert(row.end() - 1, trim_text(r));
    rows.push_back(std::move(row));
  }
  return aligned(rows);
}

std::string status_counts(const std::vector<Record>& records) {
  std::vector<std::string> parts;
  for (Status status : kAllStatuses) {
    const auto n = std::count_if(records.begin(), records.end(),
                                 [status](const Record& r) { return r.status == status; });
    if (n > 0) parts.push_back(fmt::format("{} {}", n, to_string(status)));
  }
  return fmt::format("statuses: {}\n",
                     parts.empty() ? "none" : fmt::format("{}", fmt::join(parts, ", ")));
}

namespace {

constexpr std::string_view kBaseline = "cpu-coxdeboor";
// A T-spline scene has no cpu-coxdeboor record (it evaluates NURBS only): there the CPU of the
// speedup charts is its T-spline counterpart.
constexpr std::string_view kTSplineBaseline = "cpu-tspline";

std::string device_label(const DeviceInfo& d) {
  if (d.kind == "cpu") return fmt::format("CPU figure ({})", d.name);
  if (d.kind == "gpu") return fmt::format("GPU ({})", d.name);
  return fmt::format("{} device ({})", d.kind.empty() ? "unknown" : d.kind, d.name);
}

// "cpu-tensor f32: 12.5x cpu-coxdeboor, CPU figure (host CPU)"
std::string digest_entry(const Record& winner, const std::vector<Record>& records) {
  const auto baseline_named = [&](std::string_view name) {
    return std::find_if(records.begin(), records.end(), [&](const Record& r) {
      return r.strategy == name && r.scene == winner.scene && r.samples == winner.samples &&
             r.precision == winner.precision && r.status == Status::ok &&
             r.throughput_pts_per_s > 0;
    });
  };
  auto baseline = baseline_named(kBaseline);
  if (baseline == records.end()) baseline = baseline_named(kTSplineBaseline);
  const std::string ratio =
      baseline == records.end()
          ? fmt::format("{:.3g} points/s, no {} baseline", winner.throughput_pts_per_s, kBaseline)
          : fmt::format("{:.3g}x {}", winner.throughput_pts_per_s / baseline->throughput_pts_per_s,
                        baseline->strategy);
  return fmt::format("{} {}: {}, {}", winner.strategy, winner.precision, ratio,
                     device_label(winner.device));
}

}  // namespace

std::vector<std::string> summary_digest(const std::vector<Record>& records,
                                        const std::vector<Gate>& gates) {
  // (scene, samples) in the order the run measured them.
  std::vector<std::pair<std::string, std::string>> workloads;
  std::vector<std::string> precisions;
  for (const Record& r : records) {
    if (r.role == "limit") continue;
    const std::pair<std::string, std::string> key{r.scene, r.samples};
    if (std::find(workloads.begin(), workloads.end(), key) == workloads.end())
      workloads.push_back(key);
    if (std::find(precisions.begin(), precisions.end(), r.precision) == precisions.end())
      precisions.push_back(r.precision);
  }
  std::vector<std::string> lines = {fmt::format(
      "digest: per scene, the fastest strategy within its accuracy gates{}, evaluate throughput "
      "over {} ({} on T-spline scenes) at the same precision:",
      precisions.size() > 1 ? fmt::format(" (best of {})", fmt::join(precisions, ", ")) : "",
      kBaseline, kTSplineBaseline)};
  for (const auto& [scene, samples] : workloads) {
    std::vector<const Record*> fastest;
    for (const Record& r : records) {
      if (r.scene != scene || r.samples != samples || !passes_gates(gates, r)) continue;
      if (fastest.empty() || r.throughput_pts_per_s > fastest.front()->throughput_pts_per_s)
        fastest = {&r};
      else if (r.throughput_pts_per_s == fastest.front()->throughput_pts_per_s)
        fastest.push_back(&r);
    }
    std::string text;
    if (fastest.empty()) {
      text = "no strategy within its accuracy gates";
    } else {
      std::vector<std::string> entries;
      for (const Record* r : fastest) entries.push_back(digest_entry(*r, records));
      text = fastest.size() > 1 ? fmt::format("tie: {}", fmt::join(entries, "; ")) : entries[0];
    }
    lines.push_back(fmt::format("  {} {}: {}", scene, samples, text));
  }
  return lines;
}

std::string deforming_table(const std::vector<Record>& records) {
  std::vector<Row> rows = {{"scene", "strategy", "prec", "samples", "frame (median)", "per frame",
                            "update/prepare", "evaluate", "max_ulp (last)"}};
  for (const Record& r : records) {
    const auto frame = r.extra_phases.find("frame");
    if (r.status != Status::ok || frame == r.extra_phases.end()) continue;
    const bool updates = r.extra_phases.count("frame_update") > 0;
    rows.push_back(
        {r.scene, r.strategy, r.precision, r.samples, seconds_text(frame->second.median_s),
         updates ? "update_control_points" : "prepare again", seconds_text(r.upload.median_s),
         seconds_text(r.evaluate.median_s), r.accuracy ? max_ulp_text(*r.accuracy) : ""});
  }
  return aligned(rows);
}

}  // namespace nurbs
