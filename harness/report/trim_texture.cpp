#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

// Issue 15, 000 §4: the trim texture's misclassification rate outside the band as a function of
// its resolution R, one line per (strategy, scene, tessellation tolerance), from the runs whose
// device recorded trim_resolution (scripts/trim_texture_study.sh: one results set per R and
// tolerance), and what the lookup pass costs next to the evaluation.
ReportSection trim_texture_resolution(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& labeller = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  const auto measured = rows_where(sets, [](const Record& r) {
    return is_measurement(r) && r.trimming == "classified" &&
           r.device.details.contains("trim_resolution") && r.accuracy && r.accuracy->trim &&
           r.accuracy->trim->misclassified_rate;
  });
  auto detail = [](const Row& r, const char* key) {
    const auto it = r.record->device.details.find(key);
    return it == r.record->device.details.end() ? std::string("?") : it->second;
  };
  auto label_of = [&](const Row& r) {
    return fmt::format("{} {} tol {}{}", r.record->strategy, r.record->scene,
                       detail(r, "trim_tolerance"), labeller.machine_suffix(*r.set));
  };
  // A curve needs two resolutions: every trimmed run records its trim texture's R, and the
  // canonical runs at the default R alone are no study (the script's sets are).
  std::map<std::string, std::set<std::string>> resolutions;
  for (const Row& r : measured) resolutions[label_of(r)].insert(detail(r, "trim_resolution"));
  std::vector<Row> rows;
  for (const Row& r : measured)
    if (resolutions[label_of(r)].size() >= 2) rows.push_back(r);
  if (!show_rows(s, rows, run, sets)) return s;
  // The study's sets are folders of one parent; the script regenerates them all and the report.
  s.command = regenerate_in(run, rows.front().set->directory.parent_path().string());
  std::vector<Series> rates, drawn, classify_share;
  for (const Row& r : rows) {
    const double resolution = std::stod(detail(r, "trim_resolution"));
    const std::string label = label_of(r);
    const double rate = *r.record->accuracy->trim->misclassified_rate;
    add_point(rates, label, resolution, rate);
    // A log axis cannot show 0: such points are left off the chart (the table has them).
    add_point(drawn, label, resolution, rate > 0 ? rate : std::nan(""));
    if (const auto c = r.record->extra_phases.find("classify"); c != r.record->extra_phases.end())
      add_point(classify_share, label, resolution,
                c->second.median_s / r.record->evaluate.median_s);
  }
  charts["charts"].push_back(lines_chart(s.id, "trim texture resolution R (texels per side)",
                                         "misclassified rate outside the band", drawn, true, true));
  s.has_chart = true;
  auto rate_text = [](double x) { return fmt::format("{:.3g}", x); };
  s.tables.push_back(series_table(
      "Misclassified samples outside the band / samples outside the band, per R (columns: "
      "strategy, scene, tessellation tolerance as a fraction of the (u,v) domain diagonal)",
      "R", rates, points_text, rate_text));
  s.tables.push_back(
      series_table("classify (trim-texture lookup pass) median time / evaluate median time, per R",
                   "R", classify_share, points_text, rate_text));
  s.notes.push_back(
      "A sample is misclassified only within d = (1/2 + 2^-(s+1)) x texel diagonal + tolerance of "
      "the exact boundary (s = GL_SUBPIXEL_BITS; trim_texture::misclassification_distance, "
      "asserted per sample by tests/strategies/gl_pingpong/trim_texture_test.cpp), so the rate "
      "falls about as 1/R until the tessellation tolerance "
      "dominates. GL on llvmpipe: times are CPU times.");
  return s;
}

}  // namespace nurbs::report
