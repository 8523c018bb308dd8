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
    for (const json& row : (*set.memory)["rows"])
      table.rows.push_back(
          {text_field(row, "scene"), text_field(row, "surfaces"),
           text_field(row, "nurbs_control_points"), text_field(row, "nurbs_bytes"),
           text_field(row, "bezier_patches"), text_field(row, "bezier_control_points"),
           text_field(row, "bezier_bytes"),
           report_number(number_field(row, "bezier_bytes") / number_field(row, "nurbs_bytes")),
           text_field(row, "ksquads"), text_field(row, "bezier_shared_control_points"),
           text_field(row, "bezier_shared_bytes"),
           report_number(number_field(row, "bezier_shared_bytes") /
                         number_field(row, "nurbs_bytes"))});
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
