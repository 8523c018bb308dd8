#include "harness/memory_table.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <nlohmann/json.hpp>

#include "harness/side_files.h"
#include "reference/bezier_decomposition.h"
#include "reference/tspline.h"

namespace nurbs {

MemoryRow memory_row(const Scene& scene) {
  MemoryRow row;
  row.scene = scene.name;
  row.surfaces = scene.surfaces.size();
  for (const Surface& s : scene.surfaces) {
    if (s.is_tspline()) {
      // Its Bézier extraction (reference/tspline_extraction.h): one patch per cell of the
      // knot-line grid; the T-spline's own control points stand in the NURBS column. The cells
      // are counted from the knot lines alone (the influence index's lists are not needed).
      const TSplineSurface& t = *s.tspline;
      const std::size_t cu = tspline_cell_breaks(t.knots_u, t.u_min, t.u_max).size() - 1,
                        cv = tspline_cell_breaks(t.knots_v, t.v_min, t.v_max).size() - 1;
      const auto p = static_cast<std::size_t>(s.degree_u), q = static_cast<std::size_t>(s.degree_v);
      row.ksquads += cu * cv;
      row.nurbs_control_points += t.count();
      row.bezier_control_points += cu * cv * (p + 1) * (q + 1);
      row.bezier_shared_control_points += (cu * p + 1) * (cv * q + 1);
      continue;
    }
    const std::size_t quads = ksquad_count(s);
    const std::array<std::size_t, 2> spans = nonempty_span_counts(s);
    const auto p = static_cast<std::size_t>(s.degree_u), q = static_cast<std::size_t>(s.degree_v);
    row.ksquads += quads;
    row.nurbs_control_points += static_cast<std::size_t>(s.count_u) * s.count_v;
    row.bezier_control_points += quads * (p + 1) * (q + 1);
    row.bezier_shared_control_points += (spans[0] * p + 1) * (spans[1] * q + 1);
  }
  return row;
}

std::string memory_table_text(const std::vector<MemoryRow>& rows) {
  constexpr std::size_t kColumns = 11;
  using Line = std::array<std::string, kColumns>;
  auto kib = [](std::size_t bytes) {
    return fmt::format("{:.1f}", static_cast<double>(bytes) / 1024);
  };
  std::vector<Line> lines = {{"scene", "surfaces", "KSQuads", "NURBS#CP", "NURBS#M (KiB)",
                              "Bezier#CP", "Bezier#M (KiB)", "Bezier/NURBS", "shared#CP",
                              "shared#M (KiB)", "shared/NURBS"}};
  for (const MemoryRow& r : rows)
    lines.push_back({r.scene, std::to_string(r.surfaces), std::to_string(r.ksquads),
                     std::to_string(r.nurbs_control_points), kib(r.nurbs_bytes()),
                     std::to_string(r.bezier_control_points), kib(r.bezier_bytes()),
                     fmt::format("{:.2f}", r.ratio()),
                     std::to_string(r.bezier_shared_control_points), kib(r.bezier_shared_bytes()),
                     fmt::format("{:.2f}", r.shared_ratio())});
  std::array<std::size_t, kColumns> width{};
  for (const Line& line : lines)
    for (std::size_t c = 0; c < kColumns; ++c) width[c] = std::max(width[c], line[c].size());
  std::string out;
  for (const Line& line : lines) {
    out += fmt::format("{:<{}}", line[0], width[0]);
    for (std::size_t c = 1; c < kColumns; ++c) out += fmt::format("  {:>{}}", line[c], width[c]);
    out += "\n";
  }
  out += fmt::format(
      "control points as homogeneous float32 (w*x, w*y, w*z, w), {} bytes each; knots not "
      "counted; Bezier points per patch ((p+1)(q+1) each); shared: the boundary rows adjacent "
      "patches of a surface share counted once ((su*p+1)(sv*q+1) a surface); KSQuads = Bezier "
      "patches = non-empty span pairs (RPNS 2014, Table 1); a T-spline's NURBS#CP are its own "
      "control points and its patches are its Bezier extraction's, one per cell of its knot "
      "lines\n",
      kBytesPerControlPoint);
  return out;
}

nlohmann::json memory_table_json(const std::vector<MemoryRow>& rows) {
  MemoryFile file;
  file.notes = {{"control_point_format", "homogeneous float32 (w*x, w*y, w*z, w)"},
                {"bytes_per_control_point", kBytesPerControlPoint},
                {"knots_counted", false},
                {"bezier_shared_control_points",
                 "boundary rows shared by adjacent patches of one surface counted once"}};
  for (const MemoryRow& r : rows)
    file.rows.push_back({r.scene, r.surfaces, r.ksquads, r.ksquads, r.nurbs_control_points,
                         r.nurbs_bytes(), r.bezier_control_points, r.bezier_bytes(), r.ratio(),
                         r.bezier_shared_control_points, r.bezier_shared_bytes(),
                         r.shared_ratio()});
  return file;
}

}  // namespace nurbs
