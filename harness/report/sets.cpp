#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

namespace {

// A reason with what names the one surface it was given for left out, so refusals of one cause
// group: "surface 'clustered' is a NURBS surface, the strategy evaluates T-splines only" ->
// "NURBS surface, the strategy evaluates T-splines only" (refusal_reason() in strategies/ words
// every surface-kind refusal so). Any other reason is its own group, as written.
std::string reason_group(const std::string& reason) {
  if (!reason.starts_with("surface '")) return reason;
  for (const std::string_view is : {"' is a ", "' is an "})
    if (const auto at = reason.find(is); at != std::string::npos)
      return reason.substr(at + is.size());
  return reason;
}

}  // namespace

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
    std::set<std::string> devices;
    // Per (status, reason group): the scenes of those records (one scene refused at several
    // samplings or in several sets counts once).
    std::map<std::pair<std::string, std::string>, std::set<std::string>> not_measured;
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
        summary.not_measured[{std::string(to_string(r.status)), reason_group(r.reason)}].insert(
            r.scene);
    }
  ReportTable table{"Every strategy in these results",
                    {"strategy", "role", "devices", "ok / records", "not measured because"},
                    {}};
  // The scenes of each group in a table of their own, so the strategies table stays one line each.
  ReportTable scenes{"Scenes not measured, by strategy and reason",
                     {"strategy", "not measured because", "scenes"},
                     {}};
  for (const auto& [name, summary] : strategies) {
    std::vector<std::string> reasons;
    for (const auto& [why, where] : summary.not_measured) {
      const std::string reason = fmt::format("{} on {} scene{}: {}", why.first, where.size(),
                                             where.size() == 1 ? "" : "s", why.second);
      reasons.push_back(reason);
      scenes.rows.push_back({name, reason, fmt::format("{}", fmt::join(where, ", "))});
    }
    table.rows.push_back(
        {name, summary.role.empty() ? "-" : summary.role,
         summary.devices.empty() ? "-" : fmt::format("{}", fmt::join(summary.devices, "; ")),
         fmt::format("{} / {}", summary.ok, summary.total),
         reasons.empty() ? "-" : fmt::format("{}", fmt::join(reasons, "; "))});
  }
  s.tables.push_back(std::move(table));
  if (!scenes.rows.empty()) s.tables.push_back(std::move(scenes));
  return s;
}

}  // namespace nurbs::report
