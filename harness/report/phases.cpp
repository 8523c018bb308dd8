#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/kit.h"
#include "harness/report/labeller.h"

namespace nurbs::report {

ReportSection phases_section(const SectionInput& in) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  json& charts = in.charts;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  // One configuration for the chart: the (set, scene, samples, precision) with the most
  // strategies measured (ties: the most points).
  std::map<std::tuple<const ResultSet*, std::string, std::string, std::string>,
           std::pair<int, std::size_t>>
      configs;
  const auto all = rows_where(sets, is_measurement);
  for (const Row& r : all) {
    auto& c = configs[{r.set, r.record->scene, r.record->samples, r.record->precision}];
    ++c.first;
    c.second = std::max(c.second, r.record->points);
  }
  if (configs.empty()) {
    show_rows(s, {}, run, sets);
    return s;
  }
  auto best = configs.begin();
  for (auto it = configs.begin(); it != configs.end(); ++it)
    if (it->second > best->second) best = it;
  const auto& [set, scene, samples, precision] = best->first;
  std::vector<Row> rows;
  for (const Row& r : all)
    if (r.set == set && r.record->scene == scene && r.record->samples == samples &&
        r.record->precision == precision)
      rows.push_back(r);
  s.title += fmt::format(" — {} at {}, {}", scene, samples, precision);
  // The command remakes the configuration shown, not the section's default one.
  const std::string sampling =
      samples.starts_with("span") ? "--span-samples " + samples.substr(4) : "--samples " + samples;
  const json& settings = set->results.settings;
  const std::string repetitions =
      settings.is_object() && settings.contains("repetitions")
          ? fmt::format(" --repetitions {}", settings["repetitions"].dump())
          : "";
  show_rows(s, rows,
            fmt::format("nurbsbench run --scenes {} --strategies all {} --precision {}{} --out DIR",
                        scene, sampling, precision, repetitions),
            sets);
  std::set<std::string> extra;
  for (const Row& r : rows)
    for (const auto& [name, stats] : r.record->extra_phases) extra.insert(name);
  ReportTable table{"Median time per phase (setup: once, cold)",
                    {"strategy", "setup", "upload", "evaluate", "read_back", "end_to_end",
                     "evaluate share of end_to_end"},
                    {}};
  for (const std::string& e : extra) table.header.push_back(e);
  std::vector<std::string> categories;
  // classify (trimming strategies on trimmed scenes) is paid per evaluation like the others, and
  // is part of end_to_end: stacked, where some record has it.
  const bool classifies = extra.contains("classify");
  json upload = json::array(), evaluate = json::array(), classify = json::array(),
       read_back = json::array();
  for (const Row& r : rows) {
    const Record& x = *r.record;
    categories.push_back(label(r));
    upload.push_back(number_or_null(x.upload.median_s));
    evaluate.push_back(number_or_null(x.evaluate.median_s));
    const auto c = x.extra_phases.find("classify");
    classify.push_back(c == x.extra_phases.end() ? json(0.0) : number_or_null(c->second.median_s));
    read_back.push_back(number_or_null(x.read_back.median_s));
    std::vector<std::string> cells{label(r),
                                   seconds_text(x.setup_s),
                                   seconds_text(x.upload.median_s),
                                   seconds_text(x.evaluate.median_s),
                                   seconds_text(x.read_back.median_s),
                                   seconds_text(x.end_to_end.median_s),
                                   report_number(x.evaluate.median_s / x.end_to_end.median_s)};
    for (const std::string& e : extra)
      cells.push_back(x.extra_phases.contains(e) ? seconds_text(x.extra_phases.at(e).median_s)
                                                 : "-");
    table.rows.push_back(std::move(cells));
  }
  json stacks = {{{"label", "upload"}, {"values", upload}},
                 {{"label", "evaluate"}, {"values", evaluate}}};
  if (classifies) stacks.push_back({{"label", "classify"}, {"values", classify}});
  stacks.push_back({{"label", "read_back"}, {"values", read_back}});
  charts["charts"].push_back({{"id", s.id},
                              {"kind", "stacked"},
                              {"ylabel", "median time (s)"},
                              {"categories", categories},
                              {"stacks", stacks}});
  s.has_chart = true;
  s.tables.push_back(std::move(table));
  s.notes.push_back(
      "The chart stacks the phases paid per evaluation (upload, evaluate, classify where a "
      "strategy trims a trimmed scene, read_back); setup "
      "(context creation, shader/kernel compilation, first prepare) is paid once and is in the "
      "table only.");
  if (extra.size() > (classifies ? 1u : 0u))
    s.notes.push_back(
        "Extra phases (render, render_via_read_back, frame, …) are alternatives to the "
        "upload/evaluate/read_back path, so they are listed, not stacked.");
  return s;
}

}  // namespace nurbs::report
