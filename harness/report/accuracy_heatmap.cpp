#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection accuracy_heatmap(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  const auto rows =
      rows_where(sets, [](const Record& r) { return is_measurement(r) && r.accuracy.has_value(); });
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<std::string> scenes, labels;
  for (const Row& r : rows) {
    if (std::find(scenes.begin(), scenes.end(), r.record->scene) == scenes.end())
      scenes.push_back(r.record->scene);
    labels.push_back(label(r));
  }
  labels = sorted_unique(labels);
  std::map<std::pair<std::string, std::string>, double> worst;
  for (const Row& r : rows) {
    double& w = worst.try_emplace({label(r), r.record->scene}, 0.0).first->second;
    const double ulp = r.record->accuracy->max_ulp;
    if (!(ulp <= w)) w = std::isnan(ulp) ? std::numeric_limits<double>::infinity() : ulp;
  }
  json values = json::array();
  ReportTable table{
      "max_ulp (f32 ulps of the scene's largest coordinate); - = not measured", {"strategy"}, {}};
  for (const std::string& sc : scenes) table.header.push_back(sc);
  for (const std::string& l : labels) {
    json row = json::array();
    std::vector<std::string> cells{l};
    for (const std::string& sc : scenes) {
      auto it = worst.find({l, sc});
      row.push_back(it == worst.end()           ? json(nullptr)
                    : std::isfinite(it->second) ? json(it->second)
                                                : json("inf"));
      cells.push_back(it == worst.end() ? "-" : report_number(it->second));
    }
    values.push_back(row);
    table.rows.push_back(std::move(cells));
  }
  charts["charts"].push_back({{"id", s.id},
                              {"kind", "heatmap"},
                              {"rows", labels},
                              {"cols", scenes},
                              {"values", values},
                              {"colorbar", "max_ulp (log scale)"}});
  s.has_chart = true;
  s.tables.push_back(std::move(table));
  return s;
}

}  // namespace nurbs::report
