#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection accuracy_vs_degree(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  const auto rows = rows_where(sets, [](const Record& r) {
    return is_measurement(r) && r.accuracy && numbered_scene(r.scene, "degree-").has_value();
  });
  if (!show_rows(s, rows, run, sets)) return s;
  std::map<std::pair<std::string, int>, double> worst;
  for (const Row& r : rows) {
    double& w = worst.try_emplace({label(r), *numbered_scene(r.record->scene, "degree-")}, 0.0)
                    .first->second;
    const double ulp = r.record->accuracy->max_ulp;
    if (!(ulp <= w)) w = std::isnan(ulp) ? std::numeric_limits<double>::infinity() : ulp;
  }
  std::vector<Series> series;
  for (const auto& [key, ulp] : worst) add_point(series, key.first, key.second, ulp);
  charts["charts"].push_back(lines_chart(s.id, "degree", "max_ulp", series, false, true));
  s.has_chart = true;
  s.tables.push_back(series_table("max_ulp (worst over samplings) per degree", "degree", series,
                                  points_text, report_number));
  return s;
}

}  // namespace nurbs::report
