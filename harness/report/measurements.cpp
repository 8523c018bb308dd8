#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/link_limit.h"
#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection measurements_section(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  ReportSection s{in.row.id, in.row.title, context_of({}, sets), "", "", false, "", {}, {}, {}};
  ReportTable table{"", {}, {}};
  table.header = {
      "scene",    "samples",        "precision", "strategy", "device", "evaluate (median)",
      "points/s", "of store limit", "max_ulp",   "status"};
  // Trimmed scenes add a column: the strategy's misclassification, or "untrimmed".
  bool trims = false;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records) trims = trims || !r.trimming.empty();
  if (trims) table.header.insert(table.header.end() - 1, "trim");
  // Where a run measured the GPU's own copy ceiling, a column for the strategies on that device.
  bool copies = false;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records)
      copies = copies || (r.strategy == kDeviceCopyLimitName && r.status == Status::ok);
  if (copies) table.header.insert(table.header.begin() + 8, "of device copy");
  // Where a run measured an API's host<->device link, each GPU-API strategy's transfer phases
  // against it.
  bool links = false;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records)
      links = links || (link_limit_api(r.strategy) && r.status == Status::ok);
  if (links)
    table.header.insert(std::find(table.header.begin(), table.header.end(), "max_ulp"),
                        {"read_back of link", "upload of link"});
  bool passes = false;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records)
      passes = passes || (r.strategy == kFragmentPassLimitName && r.status == Status::ok);
  if (passes)
    table.header.insert(std::find(table.header.begin(), table.header.end(), "max_ulp"),
                        "of fragment pass");
  if (sets.size() > 1) table.header.insert(table.header.begin(), "set");
  bool any_limit = false, any_too_small = false;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records) {
      // The machine's ceiling for the same request (same set, scene, samples, precision).
      const std::optional<double> fraction = fraction_of_store_limit(r, set.results.records);
      const bool too_small = store_limit_too_small(r, set.results.records);
      any_limit = any_limit || fraction.has_value() || too_small;
      any_too_small = any_too_small || too_small;
      const bool ok = r.status == Status::ok;
      std::vector<std::string> cells{
          r.scene,
          r.samples,
          r.precision,
          r.strategy,
          r.device.kind.empty() ? "-" : r.device.kind,
          ok ? seconds_text(r.evaluate.median_s) : "-",
          ok ? report_number(r.throughput_pts_per_s) : "-",
          fraction    ? fmt::format("{:.1f}%", 100 * *fraction)
          : too_small ? "—†"
                      : "-",
          ok && r.accuracy ? (no_inside_samples(*r.accuracy) ? "- (0 inside)"
                                                             : report_number(r.accuracy->max_ulp))
                           : "-",
          ok ? "ok" : fmt::format("{}: {}", to_string(r.status), r.reason)};
      if (copies) {
        const std::optional<double> of_copy = fraction_of_device_copy_limit(r, set.results.records);
        cells.insert(cells.begin() + 8, of_copy ? fmt::format("{:.1f}%", 100 * *of_copy) : "-");
      }
      if (links) {
        const auto percent = [&](LinkPhase phase) {
          const std::optional<double> f = fraction_of_link(r, set.results.records, phase);
          return f ? fmt::format("{:.1f}%", 100 * *f) : std::string("-");
        };
        cells.insert(cells.end() - 2,  // before max_ulp and status, as in the header
                     {percent(LinkPhase::read_back), percent(LinkPhase::upload)});
      }
      if (passes) {
        const std::optional<double> f = fraction_of_fragment_pass(r, set.results.records);
        cells.insert(cells.end() - 2, f ? fmt::format("{:.1f}%", 100 * *f) : std::string("-"));
      }
      if (trims) cells.insert(cells.end() - 1, r.trimming.empty() ? "-" : trim_text(r));
      if (sets.size() > 1) cells.insert(cells.begin(), label.set_name(set));
      table.rows.push_back(std::move(cells));
    }
  if (trims)
    s.notes.push_back(
        "trim (trimmed scenes): errors are over the samples the reference classifies inside the "
        "faces; a strategy that trims is scored for classification outside the boundary band "
        "(misclassified count and rate over those samples; boundary = samples within the band, "
        "not scored); untrimmed = the strategy evaluated the whole surfaces.");
  if (!any_limit)
    s.notes.push_back(
        "No limit-store-bandwidth rows in these results (run with --strategies all, or add "
        "limit-store-bandwidth to the list), so there is no store-limit fraction.");
  else
    s.notes.push_back(
        "of store limit = the strategy's points/s over the limit-store-bandwidth row's points/s "
        "for the same scene, samples and precision: the fraction of the machine's write bandwidth "
        "its output reaches.");
  if (copies)
    s.notes.push_back(
        "of device copy = the strategy's points/s over the limit-device-copy row's points/s for "
        "the same scene, samples and precision, for strategies on the device that copied: the "
        "fraction of the device's own copy bandwidth (a copy of the output's bytes, which reads "
        "them too) its output reaches. On lavapipe the device is the host: a CPU figure.");
  if (links)
    s.notes.push_back(
        "read_back of link = the limit-link-<api> row's read-back time for the same scene, "
        "samples and precision on the strategy's device over the strategy's read_back median: "
        "the fraction of what the API's own copy of the result's bytes into pinned memory allows "
        "(the row moves exactly the result's bytes). upload of link = the strategy's upload "
        "bandwidth (the bytes its prepare sends, device detail bytes_uploaded, over its upload "
        "median) over the row's; '-' where the strategy does not say its bytes. On llvmpipe, "
        "lavapipe and PoCL the link is a memcpy: a CPU figure.");
  if (passes)
    s.notes.push_back(
        "of fragment pass = a GL strategy's points/s (evaluate, wall clock) over the "
        "limit-gl-fragment-pass row's for the same scene, samples and precision on the same "
        "device: a constant-colour fragment pass writing one RGBA32F pixel per point, the most a "
        "GL evaluation could reach if writing its output once were all it did.");
  if (any_too_small)
    s.notes.push_back(fmt::format(
        "—†: the limit row's output is under {} KiB, where a store pass times the threads' fork "
        "and join rather than the memory, so no fraction is given.",
        kStoreLimitMinBytes / 1024));
  s.tables.push_back(std::move(table));
  return s;
}

}  // namespace nurbs::report
