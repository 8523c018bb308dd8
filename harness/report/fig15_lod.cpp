#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection fig15_lod(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  // "full": 002's baseline (evaluate + read back + vertex upload + index rebuild); lod.json files
  // written before it was measured lack it and its draws, shown "n/a".
  ReportTable times{"Median times of one LOD change (from lod.json)",
                    {"scene", "samples", "device", "coarser by Haar", "coarser by re-evaluation",
                     "coarser by full re-evaluation", "Haar speed-up", "Haar speed-up (full)",
                     "finer by Haar", "finer by re-evaluation", "finer by full re-evaluation",
                     "Haar speed-up", "Haar speed-up (full)"},
                    {}};
  ReportTable levels{
      "Each level: accuracy of its Haar averages against the reference, and its "
      "draw from the texture (level 0: the evaluated grid)",
      {"scene", "samples", "level", "level samples", "max_distance", "max_ulp", "draw",
       "index elements", "drawn pixels"},
      {}};
  std::vector<std::string> categories;
  std::vector<Series> series;
  SideFileContext context;
  for (const ResultSet& set : sets) {
    if (!set.lod) continue;
    s.command = regenerate_in(run, set.directory.string());  // where lod.json is
    context.add_file(set.lod->machine);
    for (const LodRow& row : set.lod->rows) {
      const DeviceInfo device = context.add_device(row.device);
      const double ch = row.coarser_by_haar_s, cr = row.coarser_by_reevaluation_s,
                   cf = or_nan(row.coarser_by_full_reevaluation_s), fh = row.finer_by_haar_s,
                   fr = row.finer_by_reevaluation_s, ff = or_nan(row.finer_by_full_reevaluation_s);
      const std::string& scene = row.scene;
      const std::string& samples = row.samples;
      times.rows.push_back({scene, samples, device_text(device), seconds_text(ch), seconds_text(cr),
                            seconds_text(cf), report_number(cr / ch), report_number(cf / ch),
                            seconds_text(fh), seconds_text(fr), seconds_text(ff),
                            report_number(fr / fh), report_number(ff / fh)});
      const double c = static_cast<double>(categories.size());
      categories.push_back(samples + label.side_suffix(set, sets, [](const ResultSet& o) {
        return o.lod.has_value();
      }));
      add_point(series, "coarser by Haar", c, ch);
      add_point(series, "coarser by re-evaluation", c, cr);
      add_point(series, "finer by Haar", c, fh);
      add_point(series, "finer by re-evaluation", c, fr);
      if (std::isfinite(cf)) add_point(series, "coarser by full re-evaluation", c, cf);
      if (std::isfinite(ff)) add_point(series, "finer by full re-evaluation", c, ff);
      auto draw_cells = [](const std::optional<LodDrawFields>& drawn) {
        if (!drawn) return std::vector<std::string>{"n/a", "n/a", "n/a"};
        return std::vector<std::string>{seconds_text(drawn->render_s),
                                        std::to_string(drawn->index_elements),
                                        std::to_string(drawn->drawn_pixels)};
      };
      // The evaluated grid's own draw, where the file has it (its distance is the strategy's
      // accuracy, not a level's).
      if (row.draw) {
        std::vector<std::string> cells = {scene, samples, "0", samples, "n/a", "n/a"};
        for (std::string& cell : draw_cells(row.draw)) cells.push_back(std::move(cell));
        levels.rows.push_back(std::move(cells));
      }
      for (const LodLevelRow& level : row.levels) {
        std::vector<std::string> cells = {scene,
                                          samples,
                                          std::to_string(level.level),
                                          level.samples,
                                          report_number(level.max_distance),
                                          report_number(level.max_ulp)};
        for (std::string& cell : draw_cells(level.draw)) cells.push_back(std::move(cell));
        levels.rows.push_back(std::move(cells));
      }
    }
  }
  if (!context.finish(s, !times.rows.empty(), sets)) return s;
  charts["charts"].push_back(bars_chart(s.id, "median time (s)", categories, series, true));
  s.has_chart = true;
  s.tables.push_back(std::move(times));
  if (!levels.rows.empty()) s.tables.push_back(std::move(levels));
  return s;
}

}  // namespace nurbs::report
