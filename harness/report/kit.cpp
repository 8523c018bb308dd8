#include "harness/report/kit.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/labeller.h"

namespace nurbs::report {

double number_field(const json& row, const char* key) {
  if (!row.is_object() || !row.contains(key) || !row[key].is_number())
    return std::numeric_limits<double>::quiet_NaN();
  return row[key].get<double>();
}
std::string text_field(const json& row, const char* key) {
  if (!row.is_object() || !row.contains(key)) return "n/a";
  return row[key].is_string() ? row[key].get<std::string>() : row[key].dump();
}

json number_or_null(double x) {
  return std::isfinite(x) ? json(x) : json(nullptr);
}

std::string seconds_text(double s) {
  if (!std::isfinite(s)) return report_number(s);
  if (s >= 1) return fmt::format("{:.3g} s", s);
  if (s >= 1e-3) return fmt::format("{:.3g} ms", s * 1e3);
  return fmt::format("{:.3g} us", s * 1e6);
}

// "many-64" -> 64, "degree-5" -> 5; nullopt when `scene` is not `prefix` followed by digits.
std::optional<int> numbered_scene(const std::string& scene, std::string_view prefix) {
  if (!scene.starts_with(prefix) || scene.size() == prefix.size() ||
      scene.size() > prefix.size() + 6)
    return std::nullopt;
  int n = 0;
  for (std::size_t k = prefix.size(); k < scene.size(); ++k) {
    if (scene[k] < '0' || scene[k] > '9') return std::nullopt;
    n = n * 10 + (scene[k] - '0');
  }
  return n;
}

// A measurement of the scene as given: neither a limit row nor a deforming run (whose control
// points moved every frame; only the frame section reads those).
bool is_measurement(const Record& r) {
  return r.status == Status::ok && r.role != "limit" && !r.extra_phases.contains("frame");
}
bool is_frame_measurement(const Record& r) {
  return r.status == Status::ok && r.role != "limit" && r.extra_phases.contains("frame");
}

// A GPU API implemented on the CPU (llvmpipe, lavapipe, PoCL): recorded as kind "cpu" under a
// name other than the host CPU's.
bool software_device(const DeviceInfo& d) {
  return d.kind == "cpu" && !d.name.empty() && !d.name.starts_with("host CPU");
}

std::string detail_of(const DeviceInfo& d, const char* key) {
  const auto it = d.details.find(key);
  return it == d.details.end() ? std::string() : it->second;
}

// One GPU under one name in every API: GL's renderer string adds the bus and instruction set
// ("NVIDIA H200/PCIe/SSE2") that the Vulkan and OpenCL device names lack.
std::string gpu_name(const DeviceInfo& d) {
  std::string name = d.name.substr(0, d.name.find('/'));
  while (!name.empty() && name.back() == ' ') name.pop_back();
  return name.empty() ? "unknown GPU" : name;
}

// A software stand-in by its driver: Mesa's Vulkan driver (lavapipe) reports the device name of
// its GL driver (llvmpipe), and PoCL names its device after the host CPU's architecture.
std::string stand_in_name(const DeviceInfo& d) {
  if (detail_of(d, "platform").find("Portable Computing Language") != std::string::npos ||
      detail_of(d, "device_version").find("PoCL") != std::string::npos)
    return "PoCL";
  if (d.name.starts_with("llvmpipe"))
    return detail_of(d, "api").starts_with("Vulkan") ? "lavapipe" : "llvmpipe";
  return d.name.substr(0, d.name.find(" ("));
}

// "AMD EPYC 7B13 64-Core Processor" -> "AMD EPYC 7B13": trademarks and the words every model
// carries ("Processor", "CPU", the core count the label gives anyway) do not tell machines apart.
std::string short_cpu_model(const std::string& model) {
  std::string text = model;
  for (const std::string_view mark : {"(R)", "(r)", "(TM)", "(tm)"})
    for (auto at = text.find(mark); at != std::string::npos; at = text.find(mark))
      text.erase(at, mark.size());
  std::string out;
  std::istringstream words(text);
  for (std::string word; words >> word;) {
    if (word == "Processor" || word == "CPU" || word.ends_with("-Core")) continue;
    out += (out.empty() ? "" : " ") + word;
  }
  return out.empty() ? model : out;
}

// The GPUs a set's records, and its side files' rows, ran on.
std::set<std::string> gpus_of(const ResultSet& s) {
  std::set<std::string> gpus;
  for (const Record& r : s.results.records)
    if (r.device.kind == "gpu") gpus.insert(gpu_name(r.device));
  if (s.lod)
    for (const LodRow& row : s.lod->rows)
      if (row.device.kind == "gpu") gpus.insert(gpu_name({row.device.name, "gpu", {}}));
  if (s.camera_path)
    for (const CameraPathRow& row : s.camera_path->rows)
      if (row.device.kind == "gpu") gpus.insert(gpu_name({row.device.name, "gpu", {}}));
  return gpus;
}

std::string device_text(const DeviceInfo& d) {
  const std::string name = d.name.empty() ? "unknown device" : d.name;
  if (d.kind == "gpu") return name + " (GPU)";
  if (software_device(d)) return name + " (a CPU implementation of the API, not a GPU)";
  return name;
}

// Machine (CPU model), devices and drivers, commit of the rows a section shows.
std::string context_of(const std::vector<Row>& rows, const std::vector<ResultSet>& sets) {
  std::set<const ResultSet*> used;
  std::set<std::string> devices;
  for (const Row& r : rows) {
    used.insert(r.set);
    // A refused or failed record that never reached a device names none: nothing to list.
    if (!r.record->device.name.empty()) devices.insert(device_text(r.record->device));
  }
  if (used.empty())
    for (const ResultSet& s : sets) used.insert(&s);
  std::set<std::string> machines, commits;
  for (const ResultSet* s : used) {
    machines.insert(fmt::format("{} ({} threads)",
                                s->results.machine.value("cpu_model", "unknown CPU"),
                                s->results.machine.value("threads", 0)));
    commits.insert(s->results.machine.value("git_commit", "unknown"));
  }
  std::string text = fmt::format("Machine: {}", fmt::join(machines, "; "));
  if (!devices.empty()) text += fmt::format(". Devices: {}", fmt::join(devices, "; "));
  return text + fmt::format(". Commit {}.", fmt::join(commits, ", "));
}

void add_point(std::vector<Series>& series, const std::string& label, double x, double y) {
  auto it =
      std::find_if(series.begin(), series.end(), [&](const Series& s) { return s.label == label; });
  if (it == series.end()) it = series.insert(series.end(), Series{label, {}});
  it->points.emplace_back(x, y);
}

json lines_chart(const std::string& id, const std::string& xlabel, const std::string& ylabel,
                 std::vector<Series> series, bool xlog, bool ylog) {
  json out = {{"id", id},     {"kind", "lines"}, {"xlabel", xlabel},       {"ylabel", ylabel},
              {"xlog", xlog}, {"ylog", ylog},    {"series", json::array()}};
  std::sort(series.begin(), series.end(),
            [](const Series& a, const Series& b) { return a.label < b.label; });
  for (Series& s : series) {
    std::sort(s.points.begin(), s.points.end());
    json x = json::array(), y = json::array();
    for (const auto& [px, py] : s.points) {
      x.push_back(number_or_null(px));
      y.push_back(number_or_null(py));
    }
    out["series"].push_back({{"label", s.label}, {"x", x}, {"y", y}});
  }
  return out;
}

// A table with one row per x value and one column per series (cells formatted by `format`).
ReportTable series_table(const std::string& caption, const std::string& x_header,
                         const std::vector<Series>& series,
                         const std::function<std::string(double)>& x_text,
                         const std::function<std::string(double)>& format) {
  ReportTable t{caption, {x_header}, {}};
  std::vector<double> xs;
  std::vector<std::string> labels;
  for (const Series& s : series) {
    labels.push_back(s.label);
    for (const auto& p : s.points) xs.push_back(p.first);
  }
  labels = sorted_unique(labels);
  xs = sorted_unique(xs);
  for (const std::string& l : labels) t.header.push_back(l);
  for (double x : xs) {
    std::vector<std::string> row{x_text(x)};
    for (const std::string& l : labels) {
      std::string cell = "-";
      for (const Series& s : series)
        if (s.label == l)
          for (const auto& p : s.points)
            if (p.first == x) cell = format(p.second);
      row.push_back(cell);
    }
    t.rows.push_back(std::move(row));
  }
  return t;
}

std::string regenerate_in(const std::string& run_arguments, const std::string& dir) {
  std::string run = run_arguments;
  if (const auto pos = run.rfind("DIR"); pos != std::string::npos) run.replace(pos, 3, dir);
  // A study script writes its own report (DIR/report).
  if (run.starts_with("scripts/")) return run;
  return fmt::format("{}{}nurbsbench report --results {}", run, run.empty() ? "" : " && ", dir);
}
std::string regenerate_set(const std::string& run_arguments, const ResultSet& set) {
  const nlohmann::json& settings = set.results.settings;
  const std::string dir = set.directory.string();
  const auto list = [&](const char* key) {
    std::vector<std::string> items;
    if (settings.contains(key) && settings[key].is_array())
      for (const nlohmann::json& item : settings[key])
        if (item.is_string()) items.push_back(item.get<std::string>());
    return items;
  };
  const std::vector<std::string> scenes = list("scenes"), strategies = list("strategies"),
                                 samplings = list("samplings");
  if (scenes.empty() || strategies.empty() || samplings.empty())
    return regenerate_in(run_arguments, dir);
  std::vector<std::string> grids, spans;
  for (const std::string& s : samplings) {
    if (s.starts_with("span"))
      spans.push_back(s.substr(4));
    else if (s.find('x') != std::string::npos)
      grids.push_back(s);
    else
      return regenerate_in(run_arguments, dir);  // an explicit list: its file is not recorded
  }
  std::string run = fmt::format("nurbsbench run --scenes {} --strategies {}",
                                fmt::join(scenes, ","), fmt::join(strategies, ","));
  if (!grids.empty()) run += fmt::format(" --samples {}", fmt::join(grids, ","));
  if (!spans.empty()) run += fmt::format(" --span-samples {}", fmt::join(spans, ","));
  if (settings.contains("repetitions") && settings["repetitions"].is_number_integer())
    run += fmt::format(" --repetitions {}", settings["repetitions"].get<long long>());
  if (settings.contains("precision") && settings["precision"].is_string() &&
      settings["precision"].get<std::string>() != "f32")
    run += fmt::format(" --precision {}", settings["precision"].get<std::string>());
  if (settings.value("normals", false)) run += " --normals";
  if (settings.contains("threads") && settings["threads"].is_number_integer())
    run += fmt::format(" --threads {}", settings["threads"].get<long long>());
  if (settings.contains("deforming_frames") && settings["deforming_frames"].is_number_integer() &&
      settings["deforming_frames"].get<long long>() > 0)
    run += fmt::format(" --deforming {}", settings["deforming_frames"].get<long long>());
  for (const std::string& option : list("strategy_options"))
    run += fmt::format(" --strategy-option {}", option);
  return regenerate_in(run + " --out DIR", dir);
}

std::string regenerate(const std::string& run_arguments, const std::vector<ResultSet>& sets) {
  return regenerate_in(run_arguments, sets.empty() ? "DIR" : sets.front().directory.string());
}

std::string points_text(double x) {
  return fmt::format("{}", static_cast<long long>(x));
}

std::vector<Row> rows_where(const std::vector<ResultSet>& sets,
                            const std::function<bool(const Record&)>& keep) {
  std::vector<Row> rows;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records)
      if (keep(r)) rows.push_back({&set, &r});
  return rows;
}

// Several results sets can hold the same measurement (patch144 at 64x64 is in a Fig 7 run and in
// an accuracy run): a chart keeps one row per label, scene and samples, the one from the set that
// gives the chart the most rows, so no series has two points at one x.
std::vector<Row> one_per_measurement(const std::vector<Row>& rows, const Labeller& label) {
  std::map<const ResultSet*, int> rows_of_set;
  for (const Row& r : rows) ++rows_of_set[r.set];
  std::map<std::tuple<std::string, std::string, std::string>, Row> kept;
  for (const Row& r : rows) {
    const auto [it, inserted] = kept.try_emplace({label(r), r.record->scene, r.record->samples}, r);
    if (!inserted && rows_of_set[r.set] > rows_of_set[it->second.set]) it->second = r;
  }
  std::vector<Row> out;
  for (const auto& [key, row] : kept) out.push_back(row);
  return out;
}

void set_no_data(ReportSection& s, const std::string& command) {
  s.no_data = fmt::format("no data in these results: run {}", command);
}

// A section whose data its row's `run` regenerates (DIR: where it is written).
ReportSection section(const SectionInput& in) {
  ReportSection s;
  s.id = in.row.id;
  s.title = in.row.title;
  s.command = regenerate(in.row.run, in.sets);
  return s;
}

// The rows a section shows give its context (machine, devices, commit) and the directory its
// command regenerates: the set that gives the most rows, the one its command made (the accuracy
// chart also reads the patch144 rows of a Fig 7 set, which another command made). Without rows
// the section says what to run. False: nothing to show.
bool show_rows(ReportSection& s, const std::vector<Row>& rows, const std::string& run,
               const std::vector<ResultSet>& sets) {
  s.context = context_of(rows, sets);
  if (rows.empty()) {
    set_no_data(s, s.command);
    return false;
  }
  std::map<const ResultSet*, int> rows_of_set;
  for (const Row& r : rows) ++rows_of_set[r.set];
  const ResultSet* most = rows.front().set;
  for (const auto& [set, n] : rows_of_set)
    if (n > rows_of_set[most]) most = set;
  s.command = regenerate_set(run, *most);
  return true;
}

ReportSection time_vs_points_of(const SectionInput& in, const std::string& scene) {
  const std::vector<ResultSet>& sets = in.sets;
  const Labeller& label = in.label;
  const std::string& run = in.row.run;
  ReportSection s = section(in);
  const auto rows = one_per_measurement(rows_where(sets,
                                                   [&](const Record& r) {
                                                     return is_measurement(r) && r.scene == scene &&
                                                            r.sampling == "grid";
                                                   }),
                                        label);
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<Series> series;
  for (const Row& r : rows)
    add_point(series, label(r), static_cast<double>(r.record->points), r.record->evaluate.median_s);
  in.charts["charts"].push_back(
      lines_chart(s.id, "evaluation points", "evaluate time, median (s)", series, true, true));
  s.has_chart = true;
  s.tables.push_back(series_table("Evaluate time (median) per number of points", "points", series,
                                  points_text, seconds_text));
  return s;
}

json bars_chart(const std::string& id, const std::string& ylabel,
                const std::vector<std::string>& categories, const std::vector<Series>& series,
                bool ylog) {
  json out = {{"id", id},     {"kind", "bars"},           {"ylabel", ylabel},
              {"ylog", ylog}, {"categories", categories}, {"series", json::array()}};
  for (const Series& s : series) {
    json values = json::array();
    for (std::size_t c = 0; c < categories.size(); ++c) {
      double v = std::numeric_limits<double>::quiet_NaN();
      for (const auto& p : s.points)
        if (p.first == static_cast<double>(c)) v = p.second;
      values.push_back(number_or_null(v));
    }
    out["series"].push_back({{"label", s.label}, {"values", values}});
  }
  return out;
}

ReportTable category_table(const std::string& caption, const std::string& first,
                           const std::vector<std::string>& categories,
                           const std::vector<Series>& series,
                           const std::function<std::string(double)>& format) {
  return series_table(
      caption, first, series, [&](double x) { return categories.at(static_cast<std::size_t>(x)); },
      format);
}

// The phases of one frame of 000's Fig 8 with trims, as a record measured them: evaluate, then
// classify (a strategy that trims) and draw (render: a strategy that draws from where it
// evaluated). A strategy without a render path is timed without the draw, which the table says.
double trimmed_frame_s(const Record& r) {
  double s = r.evaluate.median_s;
  for (const char* phase : {"classify", "render"})
    if (auto it = r.extra_phases.find(phase); it != r.extra_phases.end()) s += it->second.median_s;
  return s;
}
std::string trimmed_frame_phases(const Record& r) {
  std::string phases = "evaluate";
  if (r.extra_phases.contains("classify")) phases += " + classify";
  phases += r.extra_phases.contains("render") ? " + draw" : " (no draw path)";
  if (r.trimming == "untrimmed") phases += ", untrimmed";
  return phases;
}

}  // namespace nurbs::report

namespace nurbs {

std::string report_number(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  if (!std::isfinite(x)) return "n/a";
  return fmt::format("{:.3g}", x);
}

}  // namespace nurbs
