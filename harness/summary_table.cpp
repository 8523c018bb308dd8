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
