#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection fig8_trimmed_ducks(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  auto rows = one_per_measurement(
      rows_where(sets,
                 [](const Record& r) {
                   return is_measurement(r) && numbered_scene(r.scene, "many-ducks-").has_value();
                 }),
      label);
  const bool has_16 = std::any_of(rows.begin(), rows.end(),
                                  [](const Row& r) { return r.record->samples == "16x16"; });
  if (has_16) std::erase_if(rows, [](const Row& r) { return r.record->samples != "16x16"; });
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<Series> frames;
  std::map<std::string, std::string> phases;
  for (const Row& r : rows) {
    const std::string l = has_16 ? label(r) : label(r) + " " + r.record->samples;
    add_point(frames, l, *numbered_scene(r.record->scene, "many-ducks-"),
              1 / trimmed_frame_s(*r.record));
    phases.emplace(l, trimmed_frame_phases(*r.record));
  }
  charts["charts"].push_back(lines_chart(s.id, "ducks", "frames per second", frames, true, true));
  s.has_chart = true;
  s.tables.push_back(series_table("Frames per second (evaluate + classify + draw, medians)",
                                  "ducks", frames, points_text, report_number));
  ReportTable what{"What each frame holds", {"strategy", "phases timed"}, {}};
  for (const auto& [l, p] : phases) what.rows.push_back({l, p});
  s.tables.push_back(std::move(what));
  s.notes.push_back(
      "Ducks 0, 3, 6, ... are trimmed (each surface: a rounded rectangle with a hole, exact "
      "rational curves). A strategy that trims classifies every sample (classify); glu-nurbs "
      "tessellates the trimmed faces natively (its evaluate is the trimmed tessellation, and it "
      "classifies nothing: untrimmed); the others evaluate the whole surfaces (untrimmed). GPU "
      "strategies on a software rasterizer (llvmpipe, lavapipe) are CPU figures. One thread: the "
      "frame rate of one application thread, as 000 drew, and no OpenMP team to oversubscribe a "
      "shared machine.");
  return s;
}

}  // namespace nurbs::report
