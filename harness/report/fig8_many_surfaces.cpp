#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection fig8_many_surfaces(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  auto rows = one_per_measurement(rows_where(sets,
                                             [](const Record& r) {
                                               return is_measurement(r) &&
                                                      numbered_scene(r.scene, "many-").has_value();
                                             }),
                                  label);
  // The paper's 16×16 per surface when measured; otherwise every grid, labelled by it.
  const bool has_16 = std::any_of(rows.begin(), rows.end(),
                                  [](const Row& r) { return r.record->samples == "16x16"; });
  if (has_16) std::erase_if(rows, [](const Row& r) { return r.record->samples != "16x16"; });
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<Series> throughput, frames;
  for (const Row& r : rows) {
    const std::string l = has_16 ? label(r) : label(r) + " " + r.record->samples;
    const double n = *numbered_scene(r.record->scene, "many-");
    add_point(throughput, l, n, r.record->throughput_pts_per_s);
    add_point(frames, l, n, 1 / r.record->end_to_end.median_s);
  }
  charts["charts"].push_back(
      lines_chart(s.id, "surfaces", "throughput (points/s)", throughput, true, true));
  s.has_chart = true;
  s.tables.push_back(series_table("Throughput (points/s, evaluate only)", "surfaces", throughput,
                                  points_text, report_number));
  s.tables.push_back(series_table("Frames per second (upload + evaluate + read back)", "surfaces",
                                  frames, points_text, report_number));
  return s;
}

}  // namespace nurbs::report
