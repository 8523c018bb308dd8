#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection fig14_deboor_vs_basis(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::vector<std::string> scenes = {"tan16", "tan64", "tan256"};
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  auto rows = one_per_measurement(rows_where(sets,
                                             [&](const Record& r) {
                                               return is_measurement(r) && r.sampling == "grid" &&
                                                      std::find(scenes.begin(), scenes.end(),
                                                                r.scene) != scenes.end();
                                             }),
                                  label);
  // One grid for the whole chart: the one measured most often on these scenes (ties: the larger).
  std::map<std::string, std::pair<int, std::size_t>> grids;
  for (const Row& r : rows) {
    auto& g = grids[r.record->samples];
    ++g.first;
    g.second = r.record->points;
  }
  std::string grid;
  std::pair<int, std::size_t> best{0, 0};
  for (const auto& [name, count] : grids)
    if (count > best) {
      best = count;
      grid = name;
    }
  std::erase_if(rows, [&](const Row& r) { return r.record->samples != grid; });
  if (!show_rows(s, rows, run, sets)) return s;
  s.title += fmt::format(", {} samples", grid);
  std::vector<std::string> categories;
  for (const std::string& scene : scenes)
    if (std::any_of(rows.begin(), rows.end(),
                    [&](const Row& r) { return r.record->scene == scene; }))
      categories.push_back(scene);
  std::vector<Series> series;
  for (const Row& r : rows) {
    const auto c =
        std::find(categories.begin(), categories.end(), r.record->scene) - categories.begin();
    add_point(series, label(r), static_cast<double>(c), r.record->evaluate.median_s);
  }
  std::sort(series.begin(), series.end(),
            [](const Series& a, const Series& b) { return a.label < b.label; });
  charts["charts"].push_back(
      bars_chart(s.id, "evaluate time, median (s)", categories, series, true));
  s.has_chart = true;
  s.tables.push_back(category_table(fmt::format("Evaluate time (median), {} samples", grid),
                                    "scene", categories, series, seconds_text));
  s.notes.push_back(
      "The paper compares its one-pass de Boor evaluation with Krishnamurthy's basis-function "
      "passes; every strategy measured on these scenes is shown beside them.");
  // Per scene (and machine, precision) where both of glsl-deboor's draw modes were measured:
  // what one draw per span costs, from the records' draw counts and medians.
  std::vector<std::string> modes;
  for (const std::string& scene : categories) {
    std::map<std::pair<std::string, std::string>, std::pair<const Record*, const Record*>> pairs;
    for (const Row& r : rows)
      if (r.record->scene == scene && r.record->strategy == "glsl-deboor") {
        auto& [per_span, instanced] = pairs[{label.machine_suffix(*r.set), r.record->precision}];
        const auto draw = r.record->device.details.find("draw");
        (draw != r.record->device.details.end() && draw->second == "instanced" ? instanced
                                                                               : per_span) =
            r.record;
      }
    std::set<std::string> precisions;
    for (const auto& [where, pair] : pairs) precisions.insert(where.second);
    for (const auto& [where, pair] : pairs) {
      const auto& [per_span, instanced] = pair;
      if (!per_span || !instanced) continue;
      const auto draws = [](const Record& r) {
        const auto d = r.device.details.find("draws");
        return d == r.device.details.end() ? std::string("?") : d->second;
      };
      modes.push_back(
          fmt::format("{}{}{}: per span {} draws, {} s; instanced {} draws, {} s (ratio {:.2f})",
                      scene, precisions.size() > 1 ? " " + where.second : "", where.first,
                      draws(*per_span), report_number(per_span->evaluate.median_s),
                      draws(*instanced), report_number(instanced->evaluate.median_s),
                      per_span->evaluate.median_s / instanced->evaluate.median_s));
    }
  }
  if (!modes.empty())
    s.notes.push_back(
        "glsl-deboor draws one quad per non-empty knot span (the paper's form) or, with "
        "--strategy-option deboor-draw=instanced, the same quads as one instanced draw per pass "
        "and degree: the same points bit for bit, so the difference is the cost of the draws "
        "themselves (evaluate medians; ratio = per span / instanced). " +
        fmt::format("{}.", fmt::join(modes, "; ")));
  return s;
}

}  // namespace nurbs::report
