#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

// 000 §3.2 from camera_path.json: frame time and triangles per frame along the fly-in, the LOD
// path (grids from the size on screen) beside a fixed grid re-evaluated every frame.
ReportSection camera_path_section(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  ReportTable summary{"Per scene (from camera_path.json): medians over the frames",
                      {"scene", "surfaces", "device", "frames", "LOD frame", "fixed frame",
                       "fixed / LOD", "LOD triangles (first → last)", "fixed triangles",
                       "host read-backs (LOD, fixed)", "device copies (LOD, fixed)"},
                      {}};
  std::vector<Series> series;
  SideFileContext context;
  for (const ResultSet& set : sets) {
    if (!set.camera_path) continue;
    s.command = regenerate_in(run, set.directory.string());  // where camera_path.json is
    const CameraPathFile& document = *set.camera_path;
    context.add_file(document.machine);
    const std::string fixed_grid = document.fixed_samples();
    for (const CameraPathRow& row : document.rows) {
      const DeviceInfo device = context.add_device(row.device);
      const std::string& scene = row.scene;
      const std::string suffix = label.side_suffix(
          set, sets, [](const ResultSet& o) { return o.camera_path.has_value(); });
      const std::string where = fmt::format(" ({}){}", scene, suffix);
      std::string first_triangles = "n/a", last_triangles = "n/a", fixed_triangles = "n/a";
      const std::vector<CameraFrame>& frames = row.frames;
      for (const CameraFrame& frame : frames) {
        const double f = frame.frame;
        add_point(series, "frame time: LOD" + where, f, frame.lod_frame_s * 1e3);
        add_point(series, fmt::format("frame time: fixed {}{}", fixed_grid, where), f,
                  frame.fixed_frame_s * 1e3);
        add_point(series, "triangles: LOD" + where, f, static_cast<double>(frame.lod_triangles));
        add_point(series, fmt::format("triangles: fixed {}{}", fixed_grid, where), f,
                  static_cast<double>(frame.fixed_triangles));
      }
      if (!frames.empty()) {
        first_triangles = std::to_string(frames.front().lod_triangles);
        last_triangles = std::to_string(frames.back().lod_triangles);
        fixed_triangles = std::to_string(frames.front().fixed_triangles);
      }
      const double lod = row.median_lod_frame_s, fixed = row.median_fixed_frame_s;
      summary.rows.push_back(
          {scene, std::to_string(row.surfaces), device_text(device), std::to_string(frames.size()),
           seconds_text(lod), seconds_text(fixed), report_number(fixed / lod),
           fmt::format("{} → {}", first_triangles, last_triangles), fixed_triangles,
           fmt::format("{}, {}", row.lod_counts.host_read_backs, row.fixed_counts.host_read_backs),
           fmt::format("{}, {}", row.lod_counts.device_copies, row.fixed_counts.device_copies)});
    }
  }
  if (!context.finish(s, !summary.rows.empty(), sets)) return s;
  json chart = lines_chart(s.id, "frame (far → near)", "frame time (ms)", series, false, true);
  // Triangles on the right-hand axis: another unit along the same frames.
  chart["y2label"] = "triangles per frame";
  chart["y2log"] = true;
  for (json& line : chart["series"])
    if (line["label"].get<std::string>().starts_with("triangles")) line["axis"] = "y2";
  charts["charts"].push_back(std::move(chart));
  s.has_chart = true;
  s.tables.push_back(std::move(summary));
  return s;
}

}  // namespace nurbs::report
