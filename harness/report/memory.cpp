#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"

namespace nurbs::report {

ReportSection rpns_memory(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  ReportSection s = section(in);
  s.context = context_of({}, sets);
  ReportTable table{"Control-point memory (from memory.json)",
                    {"scene", "surfaces", "NURBS control points", "NURBS bytes", "Bézier patches",
                     "Bézier control points", "Bézier bytes", "Bézier / NURBS", "KSQuads",
                     "Bézier control points, shared edges once", "shared bytes", "shared / NURBS"},
                    {}};
  for (const ResultSet& set : sets) {
    if (!set.memory) continue;
    s.command = regenerate_in(in.row.run, set.directory.string());  // where memory.json is
    for (const MemoryFileRow& row : set.memory->rows) {
      const auto text = [](const std::optional<std::uint64_t>& n) {
        return n ? std::to_string(*n) : std::string("n/a");
      };
      const double nurbs = static_cast<double>(row.nurbs_bytes);
      table.rows.push_back(
          {row.scene, std::to_string(row.surfaces), std::to_string(row.nurbs_control_points),
           std::to_string(row.nurbs_bytes), std::to_string(row.bezier_patches),
           std::to_string(row.bezier_control_points), std::to_string(row.bezier_bytes),
           report_number(static_cast<double>(row.bezier_bytes) / nurbs),
           std::to_string(row.ksquads), text(row.bezier_shared_control_points),
           text(row.bezier_shared_bytes),
           report_number(row.bezier_shared_bytes
                             ? static_cast<double>(*row.bezier_shared_bytes) / nurbs
                             : std::numeric_limits<double>::quiet_NaN())});
    }
  }
  if (table.rows.empty()) {
    set_no_data(s, s.command);
  } else {
    // 003's text does not say whether a boundary row adjacent patches share is held once or by
    // each patch, so both readings are shown for the reader to hold against the paper's figures.
    s.notes.push_back(
        "Two readings of the paper's Bézier count: \"Bézier control points\" holds (p+1)(q+1) "
        "points per patch, boundary rows repeated as a patch list holds them; \"shared edges "
        "once\" holds the boundary row adjacent patches of one surface share once, "
        "(su·p+1)(sv·q+1) points for su × sv non-empty spans. n/a: a memory.json written before "
        "the second count existed.");
    s.tables.push_back(std::move(table));
  }
  return s;
}

}  // namespace nurbs::report
