#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection rpns_frame(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  // One row per label: the RPNS mappings study repeats vk-ksquad's uniform frames.
  const auto rows = one_per_measurement(rows_where(sets, is_frame_measurement), label);
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<std::string> categories;
  for (const Row& r : rows) categories.push_back(r.record->scene + " " + r.record->samples);
  categories = sorted_unique(categories);
  std::vector<Series> series;
  ReportTable table{"Per-frame time (median)",
                    {"strategy", "scene", "samples", "frame", "frames/s", "evaluate only"},
                    {}};
  for (const Row& r : rows) {
    const double frame = r.record->extra_phases.at("frame").median_s;
    const auto c =
        std::find(categories.begin(), categories.end(), r.record->scene + " " + r.record->samples) -
        categories.begin();
    add_point(series, label(r), static_cast<double>(c), frame);
    table.rows.push_back({label(r), r.record->scene, r.record->samples, seconds_text(frame),
                          report_number(1 / frame), seconds_text(r.record->evaluate.median_s)});
  }
  std::sort(series.begin(), series.end(),
            [](const Series& a, const Series& b) { return a.label < b.label; });
  charts["charts"].push_back(
      bars_chart(s.id, "time per frame, median (s)", categories, series, true));
  s.has_chart = true;
  s.tables.push_back(std::move(table));
  return s;
}

}  // namespace nurbs::report
