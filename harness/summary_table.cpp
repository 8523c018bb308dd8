#include "harness/summary_table.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <array>

namespace nurbs {

namespace {
std::string seconds_text(double s) {
  if (s >= 1) return fmt::format("{:.3f} s", s);
  if (s >= 1e-3) return fmt::format("{:.3f} ms", s * 1e3);
  return fmt::format("{:.1f} us", s * 1e6);
}
}  // namespace

std::string summary_table(const std::vector<Record>& records) {
  constexpr std::size_t kColumns = 9;
  using Row = std::array<std::string, kColumns>;
  std::vector<Row> rows = {{"scene", "strategy", "on", "prec", "samples", "evaluate (median)",
                            "points/s", "max_ulp", "status"}};
  for (const Record& r : records) {
    const bool ok = r.status == Status::ok;
    rows.push_back({r.scene, r.strategy, r.device.kind.empty() ? "-" : r.device.kind, r.precision,
                    r.samples, ok ? seconds_text(r.evaluate.median_s) : "",
                    ok ? fmt::format("{:.3g}", r.throughput_pts_per_s) : "",
                    ok && r.accuracy ? fmt::format("{:.3g}", r.accuracy->max_ulp) : "",
                    ok ? "ok" : fmt::format("{}: {}", to_string(r.status), r.reason)});
  }
  std::array<std::size_t, kColumns> width{};
  for (const Row& row : rows)
    for (std::size_t c = 0; c + 1 < kColumns; ++c) width[c] = std::max(width[c], row[c].size());
  std::string out;
  for (const Row& row : rows) {
    for (std::size_t c = 0; c < kColumns; ++c)
      out += c + 1 < kColumns ? fmt::format("{:<{}}  ", row[c], width[c]) : row[c];
    out += "\n";
  }
  return out;
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
  constexpr std::size_t kColumns = 9;
  using Row = std::array<std::string, kColumns>;
  std::vector<Row> rows = {{"scene", "strategy", "prec", "samples", "frame (median)", "per frame",
                            "update/prepare", "evaluate", "max_ulp (last)"}};
  for (const Record& r : records) {
    const auto frame = r.extra_phases.find("frame");
    if (r.status != Status::ok || frame == r.extra_phases.end()) continue;
    const bool updates = r.extra_phases.count("frame_update") > 0;
    rows.push_back({r.scene, r.strategy, r.precision, r.samples,
                    seconds_text(frame->second.median_s),
                    updates ? "update_control_points" : "prepare again",
                    seconds_text(r.upload.median_s), seconds_text(r.evaluate.median_s),
                    r.accuracy ? fmt::format("{:.3g}", r.accuracy->max_ulp) : ""});
  }
  std::array<std::size_t, kColumns> width{};
  for (const Row& row : rows)
    for (std::size_t c = 0; c < kColumns; ++c) width[c] = std::max(width[c], row[c].size());
  std::string out;
  for (const Row& row : rows) {
    for (std::size_t c = 0; c < kColumns; ++c)
      out += c + 1 < kColumns ? fmt::format("{:<{}}  ", row[c], width[c]) : row[c];
    out += "\n";
  }
  return out;
}

}  // namespace nurbs
