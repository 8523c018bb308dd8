#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

// 003 §4 maps RPNS onto the pipeline three ways (GS-based, uniform, non-uniform; adaptive is the
// uniform mapping with eq. 3's levels): vk-ksquad in each, per frame of the deforming surfaces,
// with what each mapping refused and why (the GS mapping's output limit is the paper's reason for
// dropping it). The device details a mapping records (its tests' counts) are in the table.
ReportSection rpns_mappings(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& labeller = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  // The study's sets are runs given a vk-mode (scripts/rpns_mappings.sh), one mapping each; the
  // set names the mapping, as a refused record has no device details to name it.
  std::map<const ResultSet*, std::string> mapping_of;
  for (const ResultSet& set : sets)
    if (set.results.settings.is_object())
      for (const json& o : set.results.settings.value("strategy_options", json::array()))
        if (o.is_string() && o.get<std::string>().starts_with("vk-mode="))
          mapping_of[&set] =
              "vk-ksquad (" + o.get<std::string>().substr(8) + ")" + labeller.machine_suffix(set);
  std::vector<Row> rows;
  for (const Row& r : rows_where(sets, [](const Record& r) {
         return r.strategy == "vk-ksquad" &&
                (r.status != Status::ok || r.extra_phases.contains("frame"));
       }))
    if (mapping_of.contains(r.set)) rows.push_back(r);
  if (!show_rows(s, rows, run, sets)) return s;
  // The study's sets are folders of one parent; the script regenerates them all and the report.
  s.command = regenerate_in(run, rows.front().set->directory.parent_path().string());
  std::vector<std::string> categories;
  for (const Row& r : rows) categories.push_back(r.record->scene + " " + r.record->samples);
  categories = sorted_unique(categories);
  std::vector<Series> series;
  ReportTable table{"Per-frame time (median) of each mapping, and what it recorded",
                    {"mapping", "scene", "samples", "frame", "evaluate only", "points",
                     "max error (ulps)", "status / details"},
                    {}};
  for (const Row& r : rows) {
    const Record& rec = *r.record;
    const std::string& label = mapping_of.at(r.set);
    if (rec.status != Status::ok) {
      table.rows.push_back({label, rec.scene, rec.samples, "", "", "", "",
                            std::string(to_string(rec.status)) + ": " + rec.reason});
      continue;
    }
    std::string details;
    for (const auto& [key, value] : rec.device.details)
      if (key.starts_with("nu_") || key.starts_with("vk_"))
        details += (details.empty() ? "" : ", ") + key + " " + value;
    const double frame = rec.extra_phases.at("frame").median_s;
    const auto c = std::find(categories.begin(), categories.end(), rec.scene + " " + rec.samples) -
                   categories.begin();
    add_point(series, label, static_cast<double>(c), frame);
    table.rows.push_back({label, rec.scene, rec.samples, seconds_text(frame),
                          seconds_text(rec.evaluate.median_s), std::to_string(rec.points),
                          rec.accuracy ? report_number(rec.accuracy->max_ulp) : "", details});
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
