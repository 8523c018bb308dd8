#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection sets_section(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  ReportSection s{in.row.id, in.row.title, "", "", "", false, "", {}, {}, {}};
  ReportTable machines{"Where each results set was measured",
                       {"set", "directory", "CPU", "logical cores", "threads", "OS", "commit",
                        "date (UTC)", "records"},
                       {}};
  for (const ResultSet& set : sets) {
    const json& m = set.results.machine;
    machines.rows.push_back(
        {label.set_name(set), set.directory.string(), m.value("cpu_model", "unknown"),
         m.contains("logical_cores") ? m["logical_cores"].dump() : "n/a",
         m.contains("threads") ? m["threads"].dump() : "n/a", m.value("os", "unknown"),
         m.value("git_commit", "unknown"), m.value("date_utc", "unknown"),
         std::to_string(set.results.records.size())});
  }
  s.tables.push_back(std::move(machines));

  struct Summary {
    std::string role;
    std::set<std::string> devices, reasons;
    int ok = 0, total = 0;
  };
  std::map<std::string, Summary> strategies;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records) {
      Summary& summary = strategies[r.strategy];
      summary.role = r.role;
      if (!r.device.name.empty()) summary.devices.insert(device_text(r.device));
      ++summary.total;
      if (r.status == Status::ok)
        ++summary.ok;
      else
        summary.reasons.insert(fmt::format("{}: {}", to_string(r.status), r.reason));
    }
  ReportTable table{"Every strategy in these results",
                    {"strategy", "role", "devices", "ok / records", "not measured because"},
                    {}};
  for (const auto& [name, summary] : strategies)
    table.rows.push_back(
        {name, summary.role.empty() ? "-" : summary.role,
         summary.devices.empty() ? "-" : fmt::format("{}", fmt::join(summary.devices, "; ")),
         fmt::format("{} / {}", summary.ok, summary.total),
         summary.reasons.empty() ? "-" : fmt::format("{}", fmt::join(summary.reasons, "; "))});
  s.tables.push_back(std::move(table));
  return s;
}

}  // namespace nurbs::report
