// What the report's sections share: the rows they read, the series and tables they build, the
// labels, the "regenerate" commands and context lines. Internal to harness/report/; the public
// interface is harness/report/report.h.
#pragma once

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "harness/copy_limit.h"
#include "harness/report/report.h"
#include "harness/store_limit.h"
#include "harness/summary_table.h"
#include "reference/validation.h"

namespace nurbs::report {

using nlohmann::json;
namespace fs = std::filesystem;

class Labeller;

// What a section's builder is given: the sets, their labels, the chart JSON it adds its chart to,
// its own row of the sections table (id, title, command) and the report's options.
struct SectionRow;
struct SectionInput {
  const std::vector<ResultSet>& sets;
  const Labeller& label;
  json& charts;
  const SectionRow& row;
  const ReportBuildOptions& options;
};
using SectionBuilder = ReportSection (*)(const SectionInput&);

// One row of the sections table (harness/report/sections.cpp): the only place a section is
// registered. Sections appear in the report by `order`.
struct SectionRow {
  std::string id;      // also the chart's file stem
  int order = 0;       // place in the report
  std::string title;   // the paper figure it reproduces (a section may add to it)
  std::string run;     // what makes its data ("... --out DIR"), "" where nothing does
  bool chart = false;  // draws a chart: `run` is a chart command (chart_commands())
  SectionBuilder build = nullptr;
  // False: the section is left out of this report (the optional re-evaluated images).
  bool (*wanted)(const ReportBuildOptions&) = nullptr;
};
const std::vector<SectionRow>& section_rows();

// A chart's run command (its row of the sections table); a section without one is a programming
// error.
const std::string& chart_run(std::string_view id);

struct Row {
  const ResultSet* set;
  const Record* record;
};

// Side files are written by other verbs: a missing or non-numeric field is shown as "n/a".
double number_field(const json& row, const char* key);
std::string text_field(const json& row, const char* key);
json number_or_null(double x);
// An optional field of a side file as a number, NaN ("n/a") where the file lacks it.
inline double or_nan(const std::optional<double>& x) {
  return x.value_or(std::numeric_limits<double>::quiet_NaN());
}
std::string seconds_text(double s);
// "many-64" -> 64, "degree-5" -> 5; nullopt when `scene` is not `prefix` followed by digits.
std::optional<int> numbered_scene(const std::string& scene, std::string_view prefix);
// A measurement of the scene as given: neither a limit row nor a deforming run.
bool is_measurement(const Record& r);
bool is_frame_measurement(const Record& r);
// A GPU API implemented on the CPU (llvmpipe, lavapipe, PoCL).
bool software_device(const DeviceInfo& d);
std::string detail_of(const DeviceInfo& d, const char* key);
std::string gpu_name(const DeviceInfo& d);
std::string stand_in_name(const DeviceInfo& d);
std::string short_cpu_model(const std::string& model);
std::set<std::string> gpus_of(const ResultSet& s);
std::string device_text(const DeviceInfo& d);
// Machine (CPU model), devices and drivers, commit of the rows a section shows.
std::string context_of(const std::vector<Row>& rows, const std::vector<ResultSet>& sets);

// A results set's machine field, where its machine record has one.
template <typename T>
T machine_value(const ResultSet& s, const char* key, T otherwise) {
  const json& m = s.results.machine;
  if (!m.is_object() || !m.contains(key)) return otherwise;
  try {
    return m[key].get<T>();
  } catch (const json::exception&) {
    return otherwise;
  }
}

template <typename Key>
std::vector<Key> sorted_unique(std::vector<Key> keys) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

// Series by label, in first-seen order, each a list of (x, y).
struct Series {
  std::string label;
  std::vector<std::pair<double, double>> points;
};
void add_point(std::vector<Series>& series, const std::string& label, double x, double y);
json lines_chart(const std::string& id, const std::string& xlabel, const std::string& ylabel,
                 std::vector<Series> series, bool xlog, bool ylog);
// A table with one row per x value and one column per series (cells formatted by `format`).
ReportTable series_table(const std::string& caption, const std::string& x_header,
                         const std::vector<Series>& series,
                         const std::function<std::string(double)>& x_text,
                         const std::function<std::string(double)>& format);
json bars_chart(const std::string& id, const std::string& ylabel,
                const std::vector<std::string>& categories, const std::vector<Series>& series,
                bool ylog);
ReportTable category_table(const std::string& caption, const std::string& first,
                           const std::vector<std::string>& categories,
                           const std::vector<Series>& series,
                           const std::function<std::string(double)>& format);

std::string regenerate_in(const std::string& run_arguments, const std::string& dir);
// The `nurbsbench run` command that made `set`, rebuilt from the settings its results.json
// recorded (scenes, strategies, samplings, repetitions, precision, normals, threads, deforming
// frames, strategy options), then the report on it; the chart's declared `run_arguments` where the
// set recorded no run settings (a side file's set, results from before they were recorded). The
// declared command is what a chart needs; this one is what ran: a GPU check drops or shrinks steps
// for its budget, and a set run by hand has its own lists.
std::string regenerate_set(const std::string& run_arguments, const ResultSet& set);
std::string regenerate(const std::string& run_arguments, const std::vector<ResultSet>& sets);
std::string points_text(double x);

std::vector<Row> rows_where(const std::vector<ResultSet>& sets,
                            const std::function<bool(const Record&)>& keep);
std::vector<Row> one_per_measurement(const std::vector<Row>& rows, const Labeller& label);
void set_no_data(ReportSection& s, const std::string& command);
// A section of its row of the sections table, its command regenerating into the first set.
ReportSection section(const SectionInput& in);
bool show_rows(ReportSection& s, const std::vector<Row>& rows, const std::string& run,
               const std::vector<ResultSet>& sets);
// Evaluate time against the number of grid points on one scene, a line per strategy.
ReportSection time_vs_points_of(const SectionInput& in, const std::string& scene);
// The phases of one frame of 000's Fig 8 with trims (evaluate + classify + draw).
double trimmed_frame_s(const Record& r);
std::string trimmed_frame_phases(const Record& r);

// The machines, devices and commits of the side files (lod.json, camera_path.json) a section
// reads, for its context line.
struct SideFileContext {
  std::set<std::string> machines, devices, commits;

  void add_file(const json& machine) {
    machines.insert(machine.is_object() ? machine.value("cpu_model", "unknown CPU")
                                        : "unknown CPU");
    commits.insert(machine.is_object() ? machine.value("git_commit", "unknown") : "unknown");
  }
  // A row's device, recorded.
  DeviceInfo add_device(const SideDevice& d) {
    const DeviceInfo device{d.name, d.kind, {}};
    devices.insert(device_text(device));
    return device;
  }
  // The section's context, or (nothing read) what to run instead. False: nothing to show.
  bool finish(ReportSection& s, bool any, const std::vector<ResultSet>& sets) const {
    if (!any) {
      set_no_data(s, s.command);
      s.context = context_of({}, sets);
      return false;
    }
    s.context = fmt::format("Machine: {}. Devices: {}. Commit {}.", fmt::join(machines, "; "),
                            fmt::join(devices, "; "), fmt::join(commits, ", "));
    return true;
  }
};

}  // namespace nurbs::report
