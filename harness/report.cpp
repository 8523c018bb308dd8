#include "harness/report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "harness/store_limit.h"
#include "harness/summary_table.h"
#include "reference/validation.h"
#include "scenes/json_error.h"

namespace nurbs {

using nlohmann::json;
namespace fs = std::filesystem;

const std::vector<ChartCommand>& chart_commands() {
  // The scenes, samples, repetitions and frames of scripts/canonical.sh, which made the committed
  // results: a line here that differs from the script regenerates something else.
  static const std::vector<ChartCommand> commands = {
      {"fig7_time_vs_points",
       "nurbsbench run --scenes patch144 --strategies all --samples "
       "4x4,8x8,16x16,32x32,64x64,128x128,256x256,512x512,1024x1024,2048x2048 --repetitions 3 "
       "--out DIR"},
      {"fig9_tspline_time_vs_points",
       "nurbsbench run --scenes tspline-tjunction --strategies all --samples "
       "4x4,8x8,16x16,32x32,64x64,128x128,256x256,512x512,1024x1024 --repetitions 3 --out DIR"},
      {"fig14_deboor_vs_basis",
       "nurbsbench run --scenes tan16,tan64,tan256 --strategies all --samples 256x256 "
       "--repetitions 5 --out DIR"},
      {"fig15_lod", "nurbsbench lod --samples 128x128,512x512,1024x1024 --out DIR"},
      {"camera_path",
       "nurbsbench camera-path --scenes teapot --frames 60 --viewport 640x480 "
       "--pixels-per-sample 4 --fixed-samples 64x64 --out DIR"},
      {"rpns_frame",
       "nurbsbench run --scenes teapot,patch144,many-256 --strategies all --samples 16x16 "
       "--repetitions 1 --deforming 30 --out DIR"},
      // A script, not a verb: one deforming run of vk-ksquad per mapping under DIR, then its
      // own report there; canonical.sh also hands those sets to the machine's report.
      {"rpns_mappings",
       "scripts/rpns_mappings.sh --modes uniform,adaptive,gs,nonuniform --scenes teapot,patch144 "
       "--samples 16x16 --span-samples 4 --deforming 30 --repetitions 1 --out DIR"},
      {"fig8_many_surfaces",
       "nurbsbench run --scenes many-1,many-4,many-16,many-64,many-256,many-1024,many-4096 "
       "--strategies all --samples 16x16 --repetitions 3 --out DIR"},
      {"fig8_trimmed_ducks",
       "nurbsbench run --scenes many-ducks-1,many-ducks-2,many-ducks-4,many-ducks-8,many-ducks-16,"
       "many-ducks-32,many-ducks-64 --strategies all --samples 16x16 --repetitions 5 --threads 1 "
       "--out DIR"},
      {"accuracy_heatmap",
       "nurbsbench run --scenes default --strategies all --samples 64x64 --repetitions 3 --out "
       "DIR"},
      {"accuracy_vs_degree",
       "nurbsbench run --scenes degree-1,degree-2,degree-3,degree-4,degree-5,degree-6,degree-7,"
       "degree-8,degree-9 --strategies all --samples 64x64 --repetitions 3 --out DIR"},
      {"phases",
       "nurbsbench run --scenes patch144 --strategies all --samples 256x256 --repetitions 3 --out "
       "DIR"},
      // A script, not a verb: one run per (R, tolerance) under DIR, then its own report there.
      {"trim_texture_resolution",
       "scripts/trim_texture_study.sh --resolutions 64,128,256,512,1024,2048,4096 --tolerances "
       "1e-2,1e-3,1e-5 --samples 256x256 --repetitions 3 --out DIR"},
  };
  return commands;
}

namespace {

// A chart's row of chart_commands(); a section without one is a programming error.
const std::string& chart_run(std::string_view id) {
  for (const ChartCommand& c : chart_commands())
    if (c.id == id) return c.run;
  throw std::logic_error(fmt::format("chart {} has no row in chart_commands()", id));
}

std::optional<json> read_side_file(const fs::path& path, std::string_view format) {
  if (!fs::exists(path)) return std::nullopt;
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  json document;
  try {
    document = json::parse(text.str());
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: not JSON: {}", path.string(), json_error_text(e)));
  }
  if (!document.is_object() || !document.contains("format") || document["format"] != format)
    throw InputError(fmt::format("{}: format = {}: must be \"{}\"", path.string(),
                                 document.is_object() && document.contains("format")
                                     ? document["format"].dump()
                                     : "(missing)",
                                 format));
  if (!document.contains("rows") || !document["rows"].is_array())
    throw InputError(
        fmt::format("{}: rows = {}: must be a list", path.string(),
                    document.contains("rows") ? document["rows"].dump() : "(missing)"));
  for (std::size_t i = 0; i < document["rows"].size(); ++i)
    if (!document["rows"][i].is_object())
      throw InputError(fmt::format("{}: rows[{}] = {}: must be an object", path.string(), i,
                                   document["rows"][i].dump()));
  return document;
}

// Side files are written by other verbs: a missing or non-numeric field is shown as "n/a".
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

struct Row {
  const ResultSet* set;
  const Record* record;
};

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

// The GPUs a set's records, and its side files' rows, ran on.
std::set<std::string> gpus_of(const ResultSet& s) {
  std::set<std::string> gpus;
  for (const Record& r : s.results.records)
    if (r.device.kind == "gpu") gpus.insert(gpu_name(r.device));
  for (const std::optional<json>* side : {&s.lod, &s.camera_path})
    if (*side)
      for (const json& row : (**side)["rows"])
        if (row.contains("device") && row["device"].is_object() &&
            row["device"].value("kind", "") == "gpu")
          gpus.insert(gpu_name({text_field(row["device"], "name"), "gpu", {}}));
  return gpus;
}

// Labels name the strategy; the precision and the machine only where the report holds more than
// one of them, so a single run's chart reads "cpu-tensor", not "cpu-tensor f32 [NVIDIA H200]".
// A machine is its CPU model, core count and GPUs: the sets of one machine (each a directory
// named after its chart, the same name on every machine) are one series, another machine's the
// series beside it. glsl-deboor's instanced draw mode (device detail "draw") and vk-ksquad's
// mappings other than uniform (detail "vk_mode") are series of their own beside the default, so
// a chart shows each where several were measured.
class Labeller {
 public:
  explicit Labeller(const std::vector<ResultSet>& sets) {
    std::set<std::string> precisions;
    // Per machine: its GPUs, else the CPU, named as briefly as still tells the machines apart.
    struct Machine {
      std::string gpus, cpu, full_cpu, cores;
    };
    std::map<std::string, Machine> machines;
    std::map<const ResultSet*, std::string> key_of;
    for (const ResultSet& s : sets) {
      for (const Record& r : s.results.records) precisions.insert(r.precision);
      Machine m;
      m.full_cpu = machine_value<std::string>(s, "cpu_model", "unknown CPU");
      m.cpu = short_cpu_model(m.full_cpu);
      const int cores = machine_value<int>(s, "logical_cores", machine_value<int>(s, "threads", 0));
      m.cores = cores > 0 ? fmt::format(" {}t", cores) : "";
      m.gpus = fmt::format("{}", fmt::join(gpus_of(s), " + "));
      const std::string key = m.full_cpu + "|" + m.cores + "|" + m.gpus;
      machines.emplace(key, m);
      key_of[&s] = key;
    }
    by_precision_ = precisions.size() > 1;
    if (machines.size() < 2) return;
    const std::vector<std::function<std::string(const Machine&)>> levels = {
        [](const Machine& m) { return m.gpus.empty() ? m.cpu + m.cores : m.gpus; },
        [](const Machine& m) { return (m.gpus.empty() ? "" : m.gpus + ", ") + m.cpu + m.cores; },
        [](const Machine& m) {
          return (m.gpus.empty() ? "" : m.gpus + ", ") + m.full_cpu + m.cores;
        }};
    for (const auto& level : levels) {
      std::set<std::string> labels;
      for (const auto& [key, m] : machines) labels.insert(level(m));
      if (labels.size() < machines.size() && &level != &levels.back()) continue;
      for (const auto& [set, key] : key_of) machine_[set] = level(machines.at(key));
      break;
    }
  }
  std::string operator()(const Row& row) const {
    std::string label = row.record->strategy;
    const auto draw = row.record->device.details.find("draw");
    if (draw != row.record->device.details.end() && draw->second == "instanced")
      label += " (instanced)";
    // vk-ksquad's mappings of 003 §4 (uniform, the default, is unlabelled), and where the
    // adaptive test's corners were evaluated when it is the host.
    const auto mode = row.record->device.details.find("vk_mode");
    if (mode != row.record->device.details.end() && mode->second != "uniform") {
      const auto corners = row.record->device.details.find("vk_corners");
      const bool host = corners != row.record->device.details.end() && corners->second == "host";
      label += " (" + mode->second + (host ? ", host corners" : "") + ")";
    }
    if (by_precision_) label += " " + row.record->precision;
    return label + machine_suffix(*row.set);
  }
  // The machine a set was measured on, "" where the report holds one machine.
  std::string machine(const ResultSet& set) const {
    const auto it = machine_.find(&set);
    return it == machine_.end() ? "" : it->second;
  }
  std::string machine_suffix(const ResultSet& set) const {
    const std::string m = machine(set);
    return m.empty() ? "" : " [" + m + "]";
  }
  // A set in a table of several sets: its directory's name, and its machine where there are
  // several (each machine's sets carry the same directory names).
  std::string set_name(const ResultSet& set) const { return set.tag + machine_suffix(set); }
  // What tells a set's rows of a side file apart from other sets' (several sets): the machine,
  // or the set's name where another set of that machine holds the same file too.
  std::string side_suffix(const ResultSet& set, const std::vector<ResultSet>& sets,
                          const std::function<bool(const ResultSet&)>& has) const {
    if (sets.size() < 2) return "";
    const std::string m = machine(set);
    const bool shared = std::any_of(sets.begin(), sets.end(), [&](const ResultSet& other) {
      return &other != &set && has(other) && machine(other) == m;
    });
    if (m.empty() || shared) return " [" + set.tag + (m.empty() ? "" : ", " + m) + "]";
    return " [" + m + "]";
  }

 private:
  bool by_precision_ = false;
  std::map<const ResultSet*, std::string> machine_;  // empty: one machine
};

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
std::string regenerate(const std::string& run_arguments, const std::vector<ResultSet>& sets) {
  return regenerate_in(run_arguments, sets.empty() ? "DIR" : sets.front().directory.string());
}

std::string points_text(double x) {
  return fmt::format("{}", static_cast<long long>(x));
}

// ------------------------------------------------------------------------------------ sections

ReportSection sets_section(const std::vector<ResultSet>& sets, const Labeller& label) {
  ReportSection s{"results", "Results sets and strategies", "", "", "", false, "", {}, {}, {}};
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

// A section whose data `run` regenerates (DIR: where it is written).
ReportSection section(std::string id, std::string title, const std::string& run,
                      const std::vector<ResultSet>& sets) {
  ReportSection s;
  s.id = std::move(id);
  s.title = std::move(title);
  s.command = regenerate(run, sets);
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
  s.command = regenerate_in(run, most->directory.string());
  return true;
}

// Evaluate time against the number of grid points on one scene, a line per strategy.
ReportSection time_vs_points_of(const std::string& id, const std::string& title,
                                const std::string& scene, const std::vector<ResultSet>& sets,
                                const Labeller& label, json& charts) {
  const std::string& run = chart_run(id);
  ReportSection s = section(id, title, run, sets);
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
  charts["charts"].push_back(
      lines_chart(s.id, "evaluation points", "evaluate time, median (s)", series, true, true));
  s.has_chart = true;
  s.tables.push_back(series_table("Evaluate time (median) per number of points", "points", series,
                                  points_text, seconds_text));
  return s;
}

ReportSection time_vs_points(const std::vector<ResultSet>& sets, const Labeller& label,
                             json& charts) {
  return time_vs_points_of("fig7_time_vs_points",
                           "Krishnamurthy 2007 Fig 7 / Krishnamurthy-Yasui Fig 9: evaluation time "
                           "vs number of evaluation points (patch144, 144 control points)",
                           "patch144", sets, label, charts);
}

// 001 could not time T-splines ("due to limitations of the hardware we were not able to implement
// T-spline evaluation on the GPU"); this is the Fig 9 they would have drawn, on a T-mesh with
// T-junctions, every strategy that evaluates T-splines.
ReportSection tspline_time_vs_points(const std::vector<ResultSet>& sets, const Labeller& label,
                                     json& charts) {
  return time_vs_points_of("fig9_tspline_time_vs_points",
                           "Krishnamurthy-Yasui Fig 9 for T-splines (which they could not run on "
                           "the GPU): evaluation time vs number of evaluation points "
                           "(tspline-tjunction, 489 control points, six T-junctions)",
                           "tspline-tjunction", sets, label, charts);
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

ReportSection deboor_vs_basis(const std::vector<ResultSet>& sets, const Labeller& label,
                              json& charts) {
  const std::vector<std::string> scenes = {"tan16", "tan64", "tan256"};
  const std::string& run = chart_run("fig14_deboor_vs_basis");
  ReportSection s =
      section("fig14_deboor_vs_basis",
              "Tan 2012 Fig 14: one-pass de Boor (glsl-deboor) vs multi-pass basis functions "
              "(gl-pingpong), 16², 64², 256² control points",
              run, sets);
  auto rows = one_per_measurement(rows_where(sets,
                                             [&](const Record& r) {
                                               return is_measurement(r) && r.sampling == "grid" &&
                                                      std::find(scenes.begin(), scenes.end(),
                                                                r.scene) != scenes.end();
                                             }),
                                  label);
  // One grid for the whole chart: the one measured most often on these scenes (ties: the larger).
  std::map<std::string, std::pair<int, std::size_t>> grids;
  for (const Row& r : rows) {
    auto& g = grids[r.record->samples];
    ++g.first;
    g.second = r.record->points;
  }
  std::string grid;
  std::pair<int, std::size_t> best{0, 0};
  for (const auto& [name, count] : grids)
    if (count > best) {
      best = count;
      grid = name;
    }
  std::erase_if(rows, [&](const Row& r) { return r.record->samples != grid; });
  if (!show_rows(s, rows, run, sets)) return s;
  s.title += fmt::format(", {} samples", grid);
  std::vector<std::string> categories;
  for (const std::string& scene : scenes)
    if (std::any_of(rows.begin(), rows.end(),
                    [&](const Row& r) { return r.record->scene == scene; }))
      categories.push_back(scene);
  std::vector<Series> series;
  for (const Row& r : rows) {
    const auto c =
        std::find(categories.begin(), categories.end(), r.record->scene) - categories.begin();
    add_point(series, label(r), static_cast<double>(c), r.record->evaluate.median_s);
  }
  std::sort(series.begin(), series.end(),
            [](const Series& a, const Series& b) { return a.label < b.label; });
  charts["charts"].push_back(
      bars_chart(s.id, "evaluate time, median (s)", categories, series, true));
  s.has_chart = true;
  s.tables.push_back(category_table(fmt::format("Evaluate time (median), {} samples", grid),
                                    "scene", categories, series, seconds_text));
  s.notes.push_back(
      "The paper compares its one-pass de Boor evaluation with Krishnamurthy's basis-function "
      "passes; every strategy measured on these scenes is shown beside them.");
  // Per scene (and machine, precision) where both of glsl-deboor's draw modes were measured:
  // what one draw per span costs, from the records' draw counts and medians.
  std::vector<std::string> modes;
  for (const std::string& scene : categories) {
    std::map<std::pair<std::string, std::string>, std::pair<const Record*, const Record*>> pairs;
    for (const Row& r : rows)
      if (r.record->scene == scene && r.record->strategy == "glsl-deboor") {
        auto& [per_span, instanced] = pairs[{label.machine_suffix(*r.set), r.record->precision}];
        const auto draw = r.record->device.details.find("draw");
        (draw != r.record->device.details.end() && draw->second == "instanced" ? instanced
                                                                               : per_span) =
            r.record;
      }
    std::set<std::string> precisions;
    for (const auto& [where, pair] : pairs) precisions.insert(where.second);
    for (const auto& [where, pair] : pairs) {
      const auto& [per_span, instanced] = pair;
      if (!per_span || !instanced) continue;
      const auto draws = [](const Record& r) {
        const auto d = r.device.details.find("draws");
        return d == r.device.details.end() ? std::string("?") : d->second;
      };
      modes.push_back(
          fmt::format("{}{}{}: per span {} draws, {} s; instanced {} draws, {} s (ratio {:.2f})",
                      scene, precisions.size() > 1 ? " " + where.second : "", where.first,
                      draws(*per_span), report_number(per_span->evaluate.median_s),
                      draws(*instanced), report_number(instanced->evaluate.median_s),
                      per_span->evaluate.median_s / instanced->evaluate.median_s));
    }
  }
  if (!modes.empty())
    s.notes.push_back(
        "glsl-deboor draws one quad per non-empty knot span (the paper's form) or, with "
        "--strategy-option deboor-draw=instanced, the same quads as one instanced draw per pass "
        "and degree: the same points bit for bit, so the difference is the cost of the draws "
        "themselves (evaluate medians; ratio = per span / instanced). " +
        fmt::format("{}.", fmt::join(modes, "; ")));
  return s;
}

// The machines, devices and commits of the side files (lod.json, camera_path.json) a section
// reads, for its context line.
struct SideFileContext {
  std::set<std::string> machines, devices, commits;

  void add_file(const json& document) {
    const json& machine = document.value("machine", json::object());
    machines.insert(machine.is_object() ? machine.value("cpu_model", "unknown CPU")
                                        : "unknown CPU");
    commits.insert(machine.is_object() ? machine.value("git_commit", "unknown") : "unknown");
  }
  // A row's "device" ({name, kind}), recorded.
  DeviceInfo add_device(const json& row) {
    DeviceInfo device;
    if (row.contains("device") && row["device"].is_object()) {
      device.name = text_field(row["device"], "name");
      device.kind = text_field(row["device"], "kind");
    }
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

ReportSection lod_section(const std::vector<ResultSet>& sets, const Labeller& label, json& charts) {
  const std::string& run = chart_run("fig15_lod");
  ReportSection s =
      section("fig15_lod",
              "Tan 2012 Fig 15: LOD change by Haar wavelet vs re-evaluation (21×23 control "
              "points; 128², 512², 1024² samples)",
              run, sets);
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
    context.add_file(*set.lod);
    for (const json& row : (*set.lod)["rows"]) {
      const DeviceInfo device = context.add_device(row);
      const double ch = number_field(row, "coarser_by_haar_s"),
                   cr = number_field(row, "coarser_by_reevaluation_s"),
                   cf = number_field(row, "coarser_by_full_reevaluation_s"),
                   fh = number_field(row, "finer_by_haar_s"),
                   fr = number_field(row, "finer_by_reevaluation_s"),
                   ff = number_field(row, "finer_by_full_reevaluation_s");
      const std::string scene = text_field(row, "scene"), samples = text_field(row, "samples");
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
      auto draw_cells = [](const json& drawn) {
        return std::vector<std::string>{seconds_text(number_field(drawn, "render_s")),
                                        text_field(drawn, "index_elements"),
                                        text_field(drawn, "drawn_pixels")};
      };
      // The evaluated grid's own draw, where the file has it (its distance is the strategy's
      // accuracy, not a level's).
      if (row.contains("render_s")) {
        std::vector<std::string> cells = {scene, samples, "0", samples, "n/a", "n/a"};
        for (std::string& cell : draw_cells(row)) cells.push_back(std::move(cell));
        levels.rows.push_back(std::move(cells));
      }
      if (row.contains("levels") && row["levels"].is_array())
        for (const json& level : row["levels"]) {
          std::vector<std::string> cells = {scene,
                                            samples,
                                            text_field(level, "level"),
                                            text_field(level, "samples"),
                                            report_number(number_field(level, "max_distance")),
                                            report_number(number_field(level, "max_ulp"))};
          for (std::string& cell : draw_cells(level)) cells.push_back(std::move(cell));
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

// 000 §3.2 from camera_path.json: frame time and triangles per frame along the fly-in, the LOD
// path (grids from the size on screen) beside a fixed grid re-evaluated every frame.
ReportSection camera_path_section(const std::vector<ResultSet>& sets, const Labeller& label,
                                  json& charts) {
  const std::string& run = chart_run("camera_path");
  ReportSection s = section("camera_path",
                            "Krishnamurthy 2007 §3.2: continuous LOD along a camera fly-in "
                            "(gl-pingpong, drawn from a device copy) vs a fixed grid",
                            run, sets);
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
    const json& document = *set.camera_path;
    context.add_file(document);
    const json& settings = document.value("settings", json::object());
    const std::string fixed_grid = text_field(settings, "fixed_samples");
    for (const json& row : document["rows"]) {
      const DeviceInfo device = context.add_device(row);
      const std::string scene = text_field(row, "scene");
      const std::string suffix = label.side_suffix(
          set, sets, [](const ResultSet& o) { return o.camera_path.has_value(); });
      const std::string where = fmt::format(" ({}){}", scene, suffix);
      std::string first_triangles = "n/a", last_triangles = "n/a", fixed_triangles = "n/a";
      const json frames = row.value("frames", json::array());
      for (const json& frame : frames) {
        const double f = number_field(frame, "frame");
        add_point(series, "frame time: LOD" + where, f, number_field(frame, "lod_frame_s") * 1e3);
        add_point(series, fmt::format("frame time: fixed {}{}", fixed_grid, where), f,
                  number_field(frame, "fixed_frame_s") * 1e3);
        add_point(series, "triangles: LOD" + where, f, number_field(frame, "lod_triangles"));
        add_point(series, fmt::format("triangles: fixed {}{}", fixed_grid, where), f,
                  number_field(frame, "fixed_triangles"));
      }
      if (frames.is_array() && !frames.empty()) {
        first_triangles = text_field(frames.front(), "lod_triangles");
        last_triangles = text_field(frames.back(), "lod_triangles");
        fixed_triangles = text_field(frames.front(), "fixed_triangles");
      }
      const double lod = number_field(row, "median_lod_frame_s"),
                   fixed = number_field(row, "median_fixed_frame_s");
      const json lod_counts = row.value("lod_counts", json::object()),
                 fixed_counts = row.value("fixed_counts", json::object());
      summary.rows.push_back(
          {scene, text_field(row, "surfaces"), device_text(device), std::to_string(frames.size()),
           seconds_text(lod), seconds_text(fixed), report_number(fixed / lod),
           fmt::format("{} → {}", first_triangles, last_triangles), fixed_triangles,
           fmt::format("{}, {}", text_field(lod_counts, "host_read_backs"),
                       text_field(fixed_counts, "host_read_backs")),
           fmt::format("{}, {}", text_field(lod_counts, "device_copies"),
                       text_field(fixed_counts, "device_copies"))});
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

ReportSection frame_section(const std::vector<ResultSet>& sets, const Labeller& label,
                            json& charts) {
  const std::string& run = chart_run("rpns_frame");
  ReportSection s = section(
      "rpns_frame", "RPNS 2014: time per frame with deforming control points (update + evaluate)",
      run, sets);
  // One row per label: the RPNS mappings study repeats vk-ksquad's uniform frames.
  const auto rows = one_per_measurement(rows_where(sets, is_frame_measurement), label);
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<std::string> categories;
  for (const Row& r : rows) categories.push_back(r.record->scene + " " + r.record->samples);
  categories = sorted_unique(categories);
  std::vector<Series> series;
  ReportTable table{"Per-frame time (median)",
                    {"strategy", "scene", "samples", "frame", "frames/s", "evaluate only"},
                    {}};
  for (const Row& r : rows) {
    const double frame = r.record->extra_phases.at("frame").median_s;
    const auto c =
        std::find(categories.begin(), categories.end(), r.record->scene + " " + r.record->samples) -
        categories.begin();
    add_point(series, label(r), static_cast<double>(c), frame);
    table.rows.push_back({label(r), r.record->scene, r.record->samples, seconds_text(frame),
                          report_number(1 / frame), seconds_text(r.record->evaluate.median_s)});
  }
  std::sort(series.begin(), series.end(),
            [](const Series& a, const Series& b) { return a.label < b.label; });
  charts["charts"].push_back(
      bars_chart(s.id, "time per frame, median (s)", categories, series, true));
  s.has_chart = true;
  s.tables.push_back(std::move(table));
  return s;
}

// 003 §4 maps RPNS onto the pipeline three ways (GS-based, uniform, non-uniform; adaptive is the
// uniform mapping with eq. 3's levels): vk-ksquad in each, per frame of the deforming surfaces,
// with what each mapping refused and why (the GS mapping's output limit is the paper's reason for
// dropping it). The device details a mapping records (its tests' counts) are in the table.
ReportSection rpns_mappings_section(const std::vector<ResultSet>& sets, const Labeller& labeller,
                                    json& charts) {
  const std::string& run = chart_run("rpns_mappings");
  ReportSection s =
      section("rpns_mappings",
              "RPNS 2014 §4: vk-ksquad's mappings onto the pipeline (GS-based, uniform, adaptive, "
              "non-uniform), time per frame with deforming control points",
              run, sets);
  // The study's sets are runs given a vk-mode (scripts/rpns_mappings.sh), one mapping each; the
  // set names the mapping, as a refused record has no device details to name it.
  std::map<const ResultSet*, std::string> mapping_of;
  for (const ResultSet& set : sets)
    if (set.results.settings.is_object())
      for (const json& o : set.results.settings.value("strategy_options", json::array()))
        if (o.is_string() && o.get<std::string>().starts_with("vk-mode="))
          mapping_of[&set] =
              "vk-ksquad (" + o.get<std::string>().substr(8) + ")" + labeller.machine_suffix(set);
  std::vector<Row> rows;
  for (const Row& r : rows_where(sets, [](const Record& r) {
         return r.strategy == "vk-ksquad" &&
                (r.status != Status::ok || r.extra_phases.contains("frame"));
       }))
    if (mapping_of.contains(r.set)) rows.push_back(r);
  if (!show_rows(s, rows, run, sets)) return s;
  // The study's sets are folders of one parent; the script regenerates them all and the report.
  s.command = regenerate_in(run, rows.front().set->directory.parent_path().string());
  std::vector<std::string> categories;
  for (const Row& r : rows) categories.push_back(r.record->scene + " " + r.record->samples);
  categories = sorted_unique(categories);
  std::vector<Series> series;
  ReportTable table{"Per-frame time (median) of each mapping, and what it recorded",
                    {"mapping", "scene", "samples", "frame", "evaluate only", "points",
                     "max error (ulps)", "status / details"},
                    {}};
  for (const Row& r : rows) {
    const Record& rec = *r.record;
    const std::string& label = mapping_of.at(r.set);
    if (rec.status != Status::ok) {
      table.rows.push_back({label, rec.scene, rec.samples, "", "", "", "",
                            std::string(to_string(rec.status)) + ": " + rec.reason});
      continue;
    }
    std::string details;
    for (const auto& [key, value] : rec.device.details)
      if (key.starts_with("nu_") || key.starts_with("vk_"))
        details += (details.empty() ? "" : ", ") + key + " " + value;
    const double frame = rec.extra_phases.at("frame").median_s;
    const auto c = std::find(categories.begin(), categories.end(), rec.scene + " " + rec.samples) -
                   categories.begin();
    add_point(series, label, static_cast<double>(c), frame);
    table.rows.push_back({label, rec.scene, rec.samples, seconds_text(frame),
                          seconds_text(rec.evaluate.median_s), std::to_string(rec.points),
                          rec.accuracy ? report_number(rec.accuracy->max_ulp) : "", details});
  }
  std::sort(series.begin(), series.end(),
            [](const Series& a, const Series& b) { return a.label < b.label; });
  charts["charts"].push_back(
      bars_chart(s.id, "time per frame, median (s)", categories, series, true));
  s.has_chart = true;
  s.tables.push_back(std::move(table));
  return s;
}

ReportSection memory_section(const std::vector<ResultSet>& sets) {
  const std::string run = "nurbsbench memory --scenes all --json > DIR/memory.json";
  ReportSection s = section(
      "rpns_memory", "RPNS 2014 Table 1: memory of NURBS vs Bézier control points", run, sets);
  s.context = context_of({}, sets);
  ReportTable table{"Control-point memory (from memory.json)",
                    {"scene", "surfaces", "NURBS control points", "NURBS bytes", "Bézier patches",
                     "Bézier control points", "Bézier bytes", "Bézier / NURBS", "KSQuads",
                     "Bézier control points, shared edges once", "shared bytes", "shared / NURBS"},
                    {}};
  for (const ResultSet& set : sets) {
    if (!set.memory) continue;
    s.command = regenerate_in(run, set.directory.string());  // where memory.json is
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

ReportSection many_surfaces(const std::vector<ResultSet>& sets, const Labeller& label,
                            json& charts) {
  const std::string& run = chart_run("fig8_many_surfaces");
  ReportSection s =
      section("fig8_many_surfaces",
              "Krishnamurthy 2007 Fig 8 style: throughput vs number of surfaces (16×16 samples "
              "each)",
              run, sets);
  auto rows = one_per_measurement(rows_where(sets,
                                             [](const Record& r) {
                                               return is_measurement(r) &&
                                                      numbered_scene(r.scene, "many-").has_value();
                                             }),
                                  label);
  // The paper's 16×16 per surface when measured; otherwise every grid, labelled by it.
  const bool has_16 = std::any_of(rows.begin(), rows.end(),
                                  [](const Row& r) { return r.record->samples == "16x16"; });
  if (has_16) std::erase_if(rows, [](const Row& r) { return r.record->samples != "16x16"; });
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<Series> throughput, frames;
  for (const Row& r : rows) {
    const std::string l = has_16 ? label(r) : label(r) + " " + r.record->samples;
    const double n = *numbered_scene(r.record->scene, "many-");
    add_point(throughput, l, n, r.record->throughput_pts_per_s);
    add_point(frames, l, n, 1 / r.record->end_to_end.median_s);
  }
  charts["charts"].push_back(
      lines_chart(s.id, "surfaces", "throughput (points/s)", throughput, true, true));
  s.has_chart = true;
  s.tables.push_back(series_table("Throughput (points/s, evaluate only)", "surfaces", throughput,
                                  points_text, report_number));
  s.tables.push_back(series_table("Frames per second (upload + evaluate + read back)", "surfaces",
                                  frames, points_text, report_number));
  return s;
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

ReportSection fig8_trimmed_ducks(const std::vector<ResultSet>& sets, const Labeller& label,
                                 json& charts) {
  const std::string& run = chart_run("fig8_trimmed_ducks");
  ReportSection s =
      section("fig8_trimmed_ducks",
              "Krishnamurthy 2007 Fig 8 as it ran: frames per second vs number of ducks, one third "
              "trimmed (many-ducks-N, 16×16 samples per surface)",
              run, sets);
  auto rows = one_per_measurement(
      rows_where(sets,
                 [](const Record& r) {
                   return is_measurement(r) && numbered_scene(r.scene, "many-ducks-").has_value();
                 }),
      label);
  const bool has_16 = std::any_of(rows.begin(), rows.end(),
                                  [](const Row& r) { return r.record->samples == "16x16"; });
  if (has_16) std::erase_if(rows, [](const Row& r) { return r.record->samples != "16x16"; });
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<Series> frames;
  std::map<std::string, std::string> phases;
  for (const Row& r : rows) {
    const std::string l = has_16 ? label(r) : label(r) + " " + r.record->samples;
    add_point(frames, l, *numbered_scene(r.record->scene, "many-ducks-"),
              1 / trimmed_frame_s(*r.record));
    phases.emplace(l, trimmed_frame_phases(*r.record));
  }
  charts["charts"].push_back(lines_chart(s.id, "ducks", "frames per second", frames, true, true));
  s.has_chart = true;
  s.tables.push_back(series_table("Frames per second (evaluate + classify + draw, medians)",
                                  "ducks", frames, points_text, report_number));
  ReportTable what{"What each frame holds", {"strategy", "phases timed"}, {}};
  for (const auto& [l, p] : phases) what.rows.push_back({l, p});
  s.tables.push_back(std::move(what));
  s.notes.push_back(
      "Ducks 0, 3, 6, ... are trimmed (each surface: a rounded rectangle with a hole, exact "
      "rational curves). A strategy that trims classifies every sample (classify); glu-nurbs "
      "tessellates the trimmed faces natively (its evaluate is the trimmed tessellation, and it "
      "classifies nothing: untrimmed); the others evaluate the whole surfaces (untrimmed). GPU "
      "strategies on a software rasterizer (llvmpipe, lavapipe) are CPU figures. One thread: the "
      "frame rate of one application thread, as 000 drew, and no OpenMP team to oversubscribe a "
      "shared machine.");
  return s;
}

ReportSection accuracy_heatmap(const std::vector<ResultSet>& sets, const Labeller& label,
                               json& charts) {
  const std::string& run = chart_run("accuracy_heatmap");
  ReportSection s =
      section("accuracy_heatmap", "Accuracy: max_ulp per strategy and scene (worst over samplings)",
              run, sets);
  const auto rows =
      rows_where(sets, [](const Record& r) { return is_measurement(r) && r.accuracy.has_value(); });
  if (!show_rows(s, rows, run, sets)) return s;
  std::vector<std::string> scenes, labels;
  for (const Row& r : rows) {
    if (std::find(scenes.begin(), scenes.end(), r.record->scene) == scenes.end())
      scenes.push_back(r.record->scene);
    labels.push_back(label(r));
  }
  labels = sorted_unique(labels);
  std::map<std::pair<std::string, std::string>, double> worst;
  for (const Row& r : rows) {
    double& w = worst.try_emplace({label(r), r.record->scene}, 0.0).first->second;
    const double ulp = r.record->accuracy->max_ulp;
    if (!(ulp <= w)) w = std::isnan(ulp) ? std::numeric_limits<double>::infinity() : ulp;
  }
  json values = json::array();
  ReportTable table{
      "max_ulp (f32 ulps of the scene's largest coordinate); - = not measured", {"strategy"}, {}};
  for (const std::string& sc : scenes) table.header.push_back(sc);
  for (const std::string& l : labels) {
    json row = json::array();
    std::vector<std::string> cells{l};
    for (const std::string& sc : scenes) {
      auto it = worst.find({l, sc});
      row.push_back(it == worst.end()           ? json(nullptr)
                    : std::isfinite(it->second) ? json(it->second)
                                                : json("inf"));
      cells.push_back(it == worst.end() ? "-" : report_number(it->second));
    }
    values.push_back(row);
    table.rows.push_back(std::move(cells));
  }
  charts["charts"].push_back({{"id", s.id},
                              {"kind", "heatmap"},
                              {"rows", labels},
                              {"cols", scenes},
                              {"values", values},
                              {"colorbar", "max_ulp (log scale)"}});
  s.has_chart = true;
  s.tables.push_back(std::move(table));
  return s;
}

ReportSection accuracy_vs_degree(const std::vector<ResultSet>& sets, const Labeller& label,
                                 json& charts) {
  const std::string& run = chart_run("accuracy_vs_degree");
  ReportSection s = section("accuracy_vs_degree",
                            "Accuracy: max_ulp vs degree (scenes degree-1 … degree-9)", run, sets);
  const auto rows = rows_where(sets, [](const Record& r) {
    return is_measurement(r) && r.accuracy && numbered_scene(r.scene, "degree-").has_value();
  });
  if (!show_rows(s, rows, run, sets)) return s;
  std::map<std::pair<std::string, int>, double> worst;
  for (const Row& r : rows) {
    double& w = worst.try_emplace({label(r), *numbered_scene(r.record->scene, "degree-")}, 0.0)
                    .first->second;
    const double ulp = r.record->accuracy->max_ulp;
    if (!(ulp <= w)) w = std::isnan(ulp) ? std::numeric_limits<double>::infinity() : ulp;
  }
  std::vector<Series> series;
  for (const auto& [key, ulp] : worst) add_point(series, key.first, key.second, ulp);
  charts["charts"].push_back(lines_chart(s.id, "degree", "max_ulp", series, false, true));
  s.has_chart = true;
  s.tables.push_back(series_table("max_ulp (worst over samplings) per degree", "degree", series,
                                  points_text, report_number));
  return s;
}

ReportSection phases_section(const std::vector<ResultSet>& sets, const Labeller& label,
                             json& charts) {
  const std::string& run = chart_run("phases");
  ReportSection s =
      section("phases", "Phase breakdown: where the time goes (setup, upload, evaluate, read back)",
              run, sets);
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

// Issue 15, 000 §4: the trim texture's misclassification rate outside the band as a function of
// its resolution R, one line per (strategy, scene, tessellation tolerance), from the runs whose
// device recorded trim_resolution (scripts/trim_texture_study.sh: one results set per R and
// tolerance), and what the lookup pass costs next to the evaluation.
ReportSection trim_texture_section(const std::vector<ResultSet>& sets, const Labeller& labeller,
                                   json& charts) {
  const std::string& run = chart_run("trim_texture_resolution");
  ReportSection s = section("trim_texture_resolution",
                            "Krishnamurthy 2007 §4: trim-texture misclassification rate outside "
                            "the band vs trim-texture resolution R",
                            run, sets);
  const auto measured = rows_where(sets, [](const Record& r) {
    return is_measurement(r) && r.trimming == "classified" &&
           r.device.details.contains("trim_resolution") && r.accuracy && r.accuracy->trim &&
           r.accuracy->trim->misclassified_rate;
  });
  auto detail = [](const Row& r, const char* key) {
    const auto it = r.record->device.details.find(key);
    return it == r.record->device.details.end() ? std::string("?") : it->second;
  };
  auto label_of = [&](const Row& r) {
    return fmt::format("{} {} tol {}{}", r.record->strategy, r.record->scene,
                       detail(r, "trim_tolerance"), labeller.machine_suffix(*r.set));
  };
  // A curve needs two resolutions: every trimmed run records its trim texture's R, and the
  // canonical runs at the default R alone are no study (the script's sets are).
  std::map<std::string, std::set<std::string>> resolutions;
  for (const Row& r : measured) resolutions[label_of(r)].insert(detail(r, "trim_resolution"));
  std::vector<Row> rows;
  for (const Row& r : measured)
    if (resolutions[label_of(r)].size() >= 2) rows.push_back(r);
  if (!show_rows(s, rows, run, sets)) return s;
  // The study's sets are folders of one parent; the script regenerates them all and the report.
  s.command = regenerate_in(run, rows.front().set->directory.parent_path().string());
  std::vector<Series> rates, drawn, classify_share;
  for (const Row& r : rows) {
    const double resolution = std::stod(detail(r, "trim_resolution"));
    const std::string label = label_of(r);
    const double rate = *r.record->accuracy->trim->misclassified_rate;
    add_point(rates, label, resolution, rate);
    // A log axis cannot show 0: such points are left off the chart (the table has them).
    add_point(drawn, label, resolution, rate > 0 ? rate : std::nan(""));
    if (const auto c = r.record->extra_phases.find("classify"); c != r.record->extra_phases.end())
      add_point(classify_share, label, resolution,
                c->second.median_s / r.record->evaluate.median_s);
  }
  charts["charts"].push_back(lines_chart(s.id, "trim texture resolution R (texels per side)",
                                         "misclassified rate outside the band", drawn, true, true));
  s.has_chart = true;
  auto rate_text = [](double x) { return fmt::format("{:.3g}", x); };
  s.tables.push_back(series_table(
      "Misclassified samples outside the band / samples outside the band, per R (columns: "
      "strategy, scene, tessellation tolerance as a fraction of the (u,v) domain diagonal)",
      "R", rates, points_text, rate_text));
  s.tables.push_back(
      series_table("classify (trim-texture lookup pass) median time / evaluate median time, per R",
                   "R", classify_share, points_text, rate_text));
  s.notes.push_back(
      "A sample is misclassified only within d = (1/2 + 2^-(s+1)) x texel diagonal + tolerance of "
      "the exact boundary (s = GL_SUBPIXEL_BITS; trim_texture::misclassification_distance, "
      "asserted per sample by tests/strategies/gl_pingpong/trim_texture_test.cpp), so the rate "
      "falls about as 1/R until the tessellation tolerance "
      "dominates. GL on llvmpipe: times are CPU times.");
  return s;
}

ReportSection measurements_section(const std::vector<ResultSet>& sets, const Labeller& label) {
  ReportSection s{"measurements",
                  "Every measurement, with throughput as a fraction of the store-bandwidth limit",
                  context_of({}, sets),
                  "",
                  "",
                  false,
                  "",
                  {},
                  {},
                  {}};
  ReportTable table{"", {}, {}};
  table.header = {
      "scene",    "samples",        "precision", "strategy", "device", "evaluate (median)",
      "points/s", "of store limit", "max_ulp",   "status"};
  // Trimmed scenes add a column: the strategy's misclassification, or "untrimmed".
  bool trims = false;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records) trims = trims || !r.trimming.empty();
  if (trims) table.header.insert(table.header.end() - 1, "trim");
  if (sets.size() > 1) table.header.insert(table.header.begin(), "set");
  bool any_limit = false, any_too_small = false;
  for (const ResultSet& set : sets)
    for (const Record& r : set.results.records) {
      // The machine's ceiling for the same request (same set, scene, samples, precision).
      const std::optional<double> fraction = fraction_of_store_limit(r, set.results.records);
      const bool too_small = store_limit_too_small(r, set.results.records);
      any_limit = any_limit || fraction.has_value() || too_small;
      any_too_small = any_too_small || too_small;
      const bool ok = r.status == Status::ok;
      std::vector<std::string> cells{
          r.scene,
          r.samples,
          r.precision,
          r.strategy,
          r.device.kind.empty() ? "-" : r.device.kind,
          ok ? seconds_text(r.evaluate.median_s) : "-",
          ok ? report_number(r.throughput_pts_per_s) : "-",
          fraction    ? fmt::format("{:.1f}%", 100 * *fraction)
          : too_small ? "—†"
                      : "-",
          ok && r.accuracy ? (no_inside_samples(*r.accuracy) ? "- (0 inside)"
                                                             : report_number(r.accuracy->max_ulp))
                           : "-",
          ok ? "ok" : fmt::format("{}: {}", to_string(r.status), r.reason)};
      if (trims) cells.insert(cells.end() - 1, r.trimming.empty() ? "-" : trim_text(r));
      if (sets.size() > 1) cells.insert(cells.begin(), label.set_name(set));
      table.rows.push_back(std::move(cells));
    }
  if (trims)
    s.notes.push_back(
        "trim (trimmed scenes): errors are over the samples the reference classifies inside the "
        "faces; a strategy that trims is scored for classification outside the boundary band "
        "(misclassified count and rate over those samples; boundary = samples within the band, "
        "not scored); untrimmed = the strategy evaluated the whole surfaces.");
  if (!any_limit)
    s.notes.push_back(
        "No limit-store-bandwidth rows in these results (run with --strategies all, or add "
        "limit-store-bandwidth to the list), so there is no store-limit fraction.");
  else
    s.notes.push_back(
        "of store limit = the strategy's points/s over the limit-store-bandwidth row's points/s "
        "for the same scene, samples and precision: the fraction of the machine's write bandwidth "
        "its output reaches.");
  if (any_too_small)
    s.notes.push_back(fmt::format(
        "—†: the limit row's output is under {} KiB, where a store pass times the threads' fork "
        "and join rather than the memory, so no fraction is given.",
        kStoreLimitMinBytes / 1024));
  s.tables.push_back(std::move(table));
  return s;
}

// ---------------------------------------------------------------------------- paper vs measured

// One configuration where both sides of a claim were measured. `fast` is the side the paper says
// is faster; the measured factor is slow_s / fast_s.
struct Comparison {
  std::string where;  // "patch144 2048x2048"
  std::string fast_name, slow_name;
  double fast_s = 0, slow_s = 0;
  DeviceInfo fast_device, slow_device;
  std::string directory;  // the results set the times come from
  // The fast side's time on its smallest workload in the same set: its fixed cost per evaluation
  // (draw calls, dispatches, transfers); NaN when the data have no smaller workload.
  double fixed_s = std::numeric_limits<double>::quiet_NaN();
  std::size_t fixed_points = 0;
  std::size_t fast_surfaces = 0, fixed_surfaces = 0;
};

// Which device a comparison's verdict speaks of: a real GPU on either side, by name (the side the
// paper says is slower is the GPU in some claims), or else the CPU, where the host and the software
// stand-ins for a GPU API are one group, as all of them are CPU figures. The rank orders a claim's
// rows: GPUs first.
struct DeviceGroup {
  int rank = 0;
  std::string name;
  auto operator<=>(const DeviceGroup&) const = default;
};
DeviceGroup device_group(const Comparison& c) {
  for (const DeviceInfo* d : {&c.fast_device, &c.slow_device})
    if (d->kind == "gpu") return {0, "GPU: " + gpu_name(*d)};
  const DeviceInfo& fast = c.fast_device;
  if (fast.kind == "cpu") return {1, "CPU"};
  if (fast.kind.empty() || fast.kind == "n/a") return {3, "unknown device"};
  return {2, fmt::format("{}: {}", fast.kind, fast.name.empty() ? "unknown device" : fast.name)};
}
// The CPU group names the stand-ins that ran in it, so a reader sees which drivers the verdict is
// about.
std::string group_label(const DeviceGroup& group, const std::vector<Comparison>& cs) {
  if (group.name != "CPU") return group.name;
  std::set<std::string> stand_ins;
  for (const Comparison& c : cs)
    for (const DeviceInfo* d : {&c.fast_device, &c.slow_device})
      if (software_device(*d)) stand_ins.insert(stand_in_name(*d));
  if (stand_ins.empty()) return "CPU (host)";
  return fmt::format("CPU stand-in ({})", fmt::join(stand_ins, ", "));
}

using Compare = std::function<std::vector<Comparison>(const std::vector<ResultSet>&)>;

struct Claim {
  std::string paper, figure, quote;
  std::string chart;        // the chart whose command makes the data
  std::string measured_as;  // which records, which ratio
  double factor = 1;        // holds when the (geometric mean) slow / fast >= factor
  std::string factor_text;  // why that factor is the claim's
  Compare compare;
};

enum class Pick { largest, smallest, each };

// Per (set, scene, samples) kept where both sides have an ok record: the fastest strategy of each
// side by `time`, so a side is the paper's method at its best here; `pick` chooses which of those
// configurations (by the fast record's points) the claim speaks of.
Compare records_compared(std::vector<std::string> fast, std::vector<std::string> slow,
                         std::function<bool(const Record&)> keep,
                         std::function<double(const Record&)> time, Pick pick) {
  return [=](const std::vector<ResultSet>& sets) {
    const auto rows = rows_where(sets, [&](const Record& r) { return keep(r) && time(r) > 0; });
    const auto fastest = [&](const std::vector<std::string>& names, const Row& like) {
      const Record* best = nullptr;
      for (const Row& r : rows)
        if (r.set == like.set && r.record->scene == like.record->scene &&
            r.record->samples == like.record->samples &&
            std::find(names.begin(), names.end(), r.record->strategy) != names.end() &&
            (!best || time(*r.record) < time(*best)))
          best = r.record;
      return best;
    };
    std::map<std::tuple<const ResultSet*, std::string, std::string>, Comparison> found;
    std::map<std::tuple<const ResultSet*, std::string, std::string>, std::size_t> points;
    for (const Row& r : rows) {
      const auto key = std::make_tuple(r.set, r.record->scene, r.record->samples);
      if (found.contains(key)) continue;
      const Record* f = fastest(fast, r);
      const Record* s = fastest(slow, r);
      if (!f || !s) continue;
      Comparison c{r.record->scene + " " + r.record->samples,
                   f->strategy,
                   s->strategy,
                   time(*f),
                   time(*s),
                   f->device,
                   s->device,
                   r.set->directory.string()};
      const Record* smallest = nullptr;
      for (const Row& o : rows)
        if (o.set == r.set && o.record->strategy == f->strategy &&
            (!smallest || o.record->points < smallest->points))
          smallest = o.record;
      if (smallest && smallest->points < f->points) {
        c.fixed_s = time(*smallest);
        c.fixed_points = smallest->points;
        c.fast_surfaces = f->surfaces;
        c.fixed_surfaces = smallest->surfaces;
      }
      found.emplace(key, c);
      points.emplace(key, f->points);
    }
    std::vector<Comparison> out;
    if (found.empty()) return out;
    if (pick == Pick::each) {
      for (const auto& [key, c] : found) out.push_back(c);
      return out;
    }
    // Per device group: each verdict speaks of its own device's largest (smallest) workload, not
    // of whichever machine measured the largest one.
    std::map<DeviceGroup, decltype(found)::const_iterator> chosen;
    for (auto it = found.cbegin(); it != found.cend(); ++it) {
      const auto [at, inserted] = chosen.try_emplace(device_group(it->second), it);
      if (!inserted && (pick == Pick::largest ? points[it->first] > points[at->second->first]
                                              : points[it->first] < points[at->second->first]))
        at->second = it;
    }
    for (const auto& [group, it] : chosen) out.push_back(it->second);
    return out;
  };
}

// 002 Fig 15 from lod.json: each LOD change (coarser, finer) by Haar against re-evaluation as the
// paper's baseline pays it (read-back, vertex upload and index rebuild included), or, in files
// from before that was measured, the de Boor passes alone.
std::vector<Comparison> lod_compared(const std::vector<ResultSet>& sets) {
  std::vector<Comparison> out;
  for (const ResultSet& set : sets) {
    if (!set.lod) continue;
    for (const json& row : (*set.lod)["rows"]) {
      DeviceInfo device;
      if (row.contains("device") && row["device"].is_object())
        device = {text_field(row["device"], "name"), text_field(row["device"], "kind"), {}};
      for (const char* way : {"coarser", "finer"}) {
        const double haar = number_field(row, fmt::format("{}_by_haar_s", way).c_str()),
                     full =
                         number_field(row, fmt::format("{}_by_full_reevaluation_s", way).c_str()),
                     again = full > 0 ? full
                                      : number_field(
                                            row, fmt::format("{}_by_reevaluation_s", way).c_str());
        if (!(haar > 0) || !(again > 0)) continue;
        out.push_back(
            {fmt::format("{} {} {}", text_field(row, "scene"), text_field(row, "samples"), way),
             "Haar", full > 0 ? "full re-evaluation" : "re-evaluation (de Boor passes alone)", haar,
             again, device, device, set.directory.string()});
      }
    }
  }
  return out;
}

bool on_patch144_grid(const Record& r) {
  return is_measurement(r) && r.scene == "patch144" && r.sampling == "grid";
}
double evaluate_time(const Record& r) {
  return r.evaluate.median_s;
}

std::vector<Claim> paper_claims() {
  const std::vector<std::string> pingpong = {"gl-pingpong", "gl-pingpong-packed"},
                                 coxdeboor = {"cpu-coxdeboor"};
  const auto frame_time = [](const Record& r) { return r.extra_phases.at("frame").median_s; };
  return {
      {"000 Krishnamurthy 2007", "Fig 7",
       "The GPU-based evaluation is faster than the CPU-based evaluation by a factor of about 50 "
       "when evaluated at a large numbers of evaluation points.",
       "fig7_time_vs_points",
       "patch144, largest grid measured: evaluate median of cpu-coxdeboor (the CPU evaluation) / "
       "the faster of gl-pingpong, gl-pingpong-packed (000's method)",
       10, "≥ 10× (about 50×; 10× on the paper's slowest card)",
       records_compared(pingpong, coxdeboor, on_patch144_grid, evaluate_time, Pick::largest)},
      {"000 Krishnamurthy 2007", "Fig 7",
       "the GPU evaluation has more overhead for very small patches and hence is not suitable for "
       "evaluating surfaces having less than 16 evaluation points.",
       "fig7_time_vs_points",
       "patch144, smallest grid measured (at most 16 points): evaluate median of the faster of "
       "gl-pingpong, gl-pingpong-packed / cpu-coxdeboor",
       1, "> 1× (the CPU is faster)",
       records_compared(
           coxdeboor, pingpong,
           [](const Record& r) { return on_patch144_grid(r) && r.points <= 16; }, evaluate_time,
           Pick::smallest)},
      {"000 Krishnamurthy 2007", "Fig 8",
       "its frame rates are unacceptably slow for more than about 100 NURBS surfaces, "
       "consistently 40-50 times slower than our GPU-based implementation.",
       "fig8_many_surfaces",
       "many-N at 16x16 per surface (untrimmed; the paper trims one third), largest N measured: "
       "end_to_end median (upload + evaluate + read back, one frame) of glu-nurbs / the faster of "
       "gl-pingpong, gl-pingpong-packed",
       40, "≥ 40× (40-50×)",
       records_compared(
           pingpong, {"glu-nurbs"},
           [](const Record& r) {
             return is_measurement(r) && numbered_scene(r.scene, "many-") && r.samples == "16x16";
           },
           [](const Record& r) { return r.end_to_end.median_s; }, Pick::largest)},
      {"000 Krishnamurthy 2007", "Fig 8",
       "its frame rates are unacceptably slow for more than about 100 NURBS surfaces, "
       "consistently 40-50 times slower than our GPU-based implementation.",
       "fig8_trimmed_ducks",
       "many-ducks-N at 16x16 per surface, one third trimmed as in the paper, largest N measured: "
       "frame time (evaluate + classify + draw, as the trimmed Fig 8 section) of glu-nurbs / the "
       "faster of gl-pingpong, gl-pingpong-packed",
       40, "≥ 40× (40-50×)",
       records_compared(
           pingpong, {"glu-nurbs"},
           [](const Record& r) {
             return is_measurement(r) && numbered_scene(r.scene, "many-ducks-") &&
                    r.samples == "16x16";
           },
           trimmed_frame_s, Pick::largest)},
      {"002 Tan 2012", "Fig 14",
       "The figure shows that our method promotes the evaluation speed orders of magnitude.",
       "fig14_deboor_vs_basis",
       "tan16, tan64, tan256 at 256x256: evaluate median of the faster of gl-pingpong, "
       "gl-pingpong-packed (the basis passes of [7]) / glsl-deboor, per scene",
       10, "≥ 10× (one order of magnitude, the least \"orders\" can mean)",
       records_compared(
           {"glsl-deboor"}, pingpong,
           [](const Record& r) {
             return is_measurement(r) && r.samples == "256x256" &&
                    (r.scene == "tan16" || r.scene == "tan64" || r.scene == "tan256");
           },
           evaluate_time, Pick::each)},
      {"002 Tan 2012", "Fig 15",
       "The figure shows that rendering with wavelet transform is 3-5 times faster than "
       "re-evaluation",
       "fig15_lod",
       "lod.json, tan21x23 at each size: median time of one LOD change by re-evaluation (the "
       "paper's baseline: evaluate, read back, upload the vertices, rebuild the index buffer; "
       "the de Boor passes alone in files without it) / by Haar, coarser and finer",
       3, "≥ 3× (3-5×)", lod_compared},
      {"003 RPNS 2014", "§1, §6 (the pipelines of Fig 3)",
       "Our experimental tests show that RPNS is several orders of magnitude faster than "
       "traditional approximations based on NURBS to Bézier conversion when considering the "
       "interactive handling of rendered models.",
       "rpns_frame",
       "deforming control points, every scene measured: frame median (update + evaluate) of "
       "cpu-bezier (decomposition redone every frame) / the faster of vk-ksquad, cl-stair, per "
       "scene",
       100, "≥ 100× (several orders of magnitude)",
       records_compared({"vk-ksquad", "cl-stair"}, {"cpu-bezier"}, is_frame_measurement, frame_time,
                        Pick::each)},
      {"003 RPNS 2014", "§1, §6 (like for like: the baseline tessellated on the GPU)",
       "Our experimental tests show that RPNS is several orders of magnitude faster than "
       "traditional approximations based on NURBS to Bézier conversion when considering the "
       "interactive handling of rendered models.",
       "rpns_frame",
       "deforming control points, every scene measured: frame median (update + evaluate) of "
       "vk-bezier (decomposition on the CPU and upload every frame, Bézier patches tessellated in "
       "vk-ksquad's pipeline shape) / vk-ksquad, per scene",
       100, "≥ 100× (several orders of magnitude)",
       records_compared({"vk-ksquad"}, {"vk-bezier"}, is_frame_measurement, frame_time,
                        Pick::each)},
      {"004 Macri 1999", "no figure (Tessellation; Optimizations)",
       "To speed up the calculation of S(u,v), we can calculate Bi,p(u) and Bj,q(v) at the "
       "subdivision points and store these in an array. [...] we can achieve better performance "
       "by using the new Streaming SIMD Extensions",
       "fig7_time_vs_points",
       "patch144, largest grid measured: evaluate median of cpu-coxdeboor (basis functions per "
       "point) / the faster of cpu-tensor (basis tables, SIMD), cpu-horner (power basis, SIMD)",
       1, "> 1× (any speed-up)",
       records_compared({"cpu-tensor", "cpu-horner"}, coxdeboor, on_patch144_grid, evaluate_time,
                        Pick::largest)},
  };
}

// The reasoning rule: what in the measurements explains a claim that does not hold, and what
// qualifies one that does. Each cause is read from the records, never written per claim.
std::vector<std::string> measured_causes(const std::vector<Comparison>& cs, bool holds) {
  std::vector<std::string> causes;
  std::set<std::string> software, differ;
  const Comparison* worst_fixed = nullptr;
  for (const Comparison& c : cs) {
    if (software_device(c.fast_device)) software.insert(c.fast_device.name);
    // Two host-CPU sides on different thread counts: the factor is partly the threads'.
    if (c.fast_device.kind == "cpu" && c.slow_device.kind == "cpu" &&
        !software_device(c.fast_device) && !software_device(c.slow_device) &&
        c.fast_device.name != c.slow_device.name)
      differ.insert(fmt::format("{} on {} vs {} on {}", c.fast_name, c.fast_device.name,
                                c.slow_name, c.slow_device.name));
    if (std::isfinite(c.fixed_s) &&
        (!worst_fixed || c.fixed_s / c.fast_s > worst_fixed->fixed_s / worst_fixed->fast_s))
      worst_fixed = &c;
  }
  if (!holds && !software.empty())
    causes.push_back(fmt::format(
        "the side claimed faster ran on {}, recorded as device kind \"cpu\": a CPU rasterizer "
        "or compute driver stands in for the GPU, so a CPU figure is compared with a CPU figure",
        fmt::join(software, ", ")));
  // A fixed cost per evaluation (draw calls, passes, dispatches) above a fifth of the time is
  // what keeps a parallel device from its throughput.
  if (!holds && worst_fixed && worst_fixed->fixed_s / worst_fixed->fast_s >= 0.2)
    causes.push_back(fmt::format(
        "{}'s fixed cost per evaluation, its time on its smallest workload ({} points: {}), is "
        "{:.0f}% of its time at {}",
        worst_fixed->fast_name, worst_fixed->fixed_points, seconds_text(worst_fixed->fixed_s),
        std::min(100.0, 100 * worst_fixed->fixed_s / worst_fixed->fast_s), worst_fixed->where));
  // Time that grows with the surfaces at no less than half its cost per surface on the smallest
  // workload is paid per surface (a draw, a pass, a dispatch each), not per point.
  for (const Comparison& c : cs)
    if (!holds && std::isfinite(c.fixed_s) && c.fixed_surfaces > 0 &&
        c.fast_surfaces > c.fixed_surfaces &&
        c.fast_s / static_cast<double>(c.fast_surfaces) >=
            0.5 * c.fixed_s / static_cast<double>(c.fixed_surfaces))
      causes.push_back(fmt::format(
          "{}'s time is paid per surface (per draw): {} per surface at {} ({} surfaces), {} on "
          "its smallest workload ({} surface{})",
          c.fast_name, seconds_text(c.fast_s / static_cast<double>(c.fast_surfaces)), c.where,
          c.fast_surfaces, seconds_text(c.fixed_s / static_cast<double>(c.fixed_surfaces)),
          c.fixed_surfaces, c.fixed_surfaces == 1 ? "" : "s"));
  if (!differ.empty())
    causes.push_back(
        fmt::format("the sides ran on different devices: {}", fmt::join(differ, "; ")));
  if (!holds && causes.empty()) causes.push_back("no cause found in these records");
  return causes;
}

std::string factor_text(double ratio) {
  const std::string text = report_number(ratio) + "×";
  return ratio < 1 ? fmt::format("{} ({}× the other way)", text, report_number(1 / ratio)) : text;
}

ReportSection claims_section(const std::vector<ResultSet>& sets) {
  ReportSection s;
  s.id = "claims";
  s.title = "Paper vs measured: which headline claims hold on this machine";
  s.context = context_of({}, sets);
  ReportTable table{
      "",
      {"paper", "figure", "claim (quoted)", "measured as", "holds when", "measured on", "measured",
       "holds?", "why (from the measurements)", "command that made the data"},
      {}};
  for (const Claim& claim : paper_claims()) {
    const std::vector<Comparison> all = claim.compare(sets);
    const std::string& run = chart_run(claim.chart);
    const std::vector<std::string> head{claim.paper, claim.figure, claim.quote, claim.measured_as,
                                        claim.factor_text};
    if (all.empty()) {
      std::vector<std::string> row = head;
      row.insert(row.end(), {"-", "-", "not measured", "these results have no records for it",
                             regenerate(run, sets)});
      table.rows.push_back(std::move(row));
      continue;
    }
    // A GPU and a CPU stand-in for it answer different questions: one verdict per device.
    std::map<DeviceGroup, std::vector<Comparison>> groups;
    for (const Comparison& c : all) groups[device_group(c)].push_back(c);
    for (const auto& [group, cs] : groups) {
      double log_sum = 0;
      std::vector<std::string> each;
      for (const Comparison& c : cs) {
        const double ratio = c.slow_s / c.fast_s;
        log_sum += std::log(ratio);
        each.push_back(fmt::format("{}: {} {} / {} {} = {}", c.where, c.slow_name,
                                   seconds_text(c.slow_s), c.fast_name, seconds_text(c.fast_s),
                                   factor_text(ratio)));
      }
      const double ratio = std::exp(log_sum / static_cast<double>(cs.size()));
      const bool holds = ratio >= claim.factor && (claim.factor > 1 || ratio > 1);
      std::string measured = fmt::format("{}", fmt::join(each, "; "));
      if (cs.size() > 1)
        measured =
            fmt::format("{} (geometric mean of {}): {}", factor_text(ratio), cs.size(), measured);
      std::vector<std::string> row = head;
      row.insert(row.end(), {group_label(group, cs), measured, holds ? "holds" : "does not hold",
                             fmt::format("{}", fmt::join(measured_causes(cs, holds), "; ")),
                             regenerate_in(run, cs.front().directory)});
      table.rows.push_back(std::move(row));
    }
  }
  s.tables.push_back(std::move(table));
  s.notes.push_back(
      "measured = the slow side's median time over the fast side's (the side the paper says is "
      "faster), in the configurations named; a side of several strategies is the fastest of "
      "them there, the paper's method at its best on this machine. Several configurations are "
      "summarised by their geometric mean.");
  s.notes.push_back(
      "Verdicts are per device: a claim has a row for each GPU its comparisons ran on (by name; a "
      "comparison with a GPU on either side is that GPU's) and one for the CPU (the host CPU and "
      "the software stand-ins for a GPU API, llvmpipe, lavapipe and PoCL, whose figures are all "
      "CPU figures), each with its own configurations, geometric mean and causes.");
  return s;
}

std::string markdown_cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

std::string html_escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

}  // namespace

std::string report_number(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  if (!std::isfinite(x)) return "n/a";
  return fmt::format("{:.3g}", x);
}

ResultSet load_result_set(const fs::path& directory) {
  ResultSet set;
  set.directory = directory;
  const fs::path dir = fs::is_directory(directory) ? directory : directory.parent_path();
  // `nurbsbench lod` and `nurbsbench camera-path` write their file alone, so their regenerate
  // commands (the verb, then report on the same directory) must read a directory without
  // results.json: a set with no records.
  const bool side_alone = fs::is_directory(directory) && !fs::exists(dir / "results.json") &&
                          (fs::exists(dir / "lod.json") || fs::exists(dir / "camera_path.json"));
  if (!side_alone) set.results = read_results(directory);
  fs::path name = fs::weakly_canonical(dir).filename();
  set.tag = name.empty() ? dir.string() : name.string();
  set.lod = read_side_file(dir / "lod.json", "nurbsbench-lod/1");
  set.memory = read_side_file(dir / "memory.json", "nurbsbench-memory/1");
  set.camera_path = read_side_file(dir / "camera_path.json", "nurbsbench-camera-path/1");
  if (side_alone)
    set.results.machine = (set.lod ? *set.lod : *set.camera_path).value("machine", json::object());
  return set;
}

Report build_report(const std::vector<ResultSet>& sets) {
  Report report;
  report.charts = {{"format", "nurbsbench-charts/1"}, {"charts", json::array()}};
  const Labeller label(sets);
  json& charts = report.charts;
  report.sections.push_back(sets_section(sets, label));
  report.sections.push_back(claims_section(sets));
  report.sections.push_back(time_vs_points(sets, label, charts));
  report.sections.push_back(tspline_time_vs_points(sets, label, charts));
  report.sections.push_back(deboor_vs_basis(sets, label, charts));
  report.sections.push_back(lod_section(sets, label, charts));
  report.sections.push_back(camera_path_section(sets, label, charts));
  report.sections.push_back(frame_section(sets, label, charts));
  report.sections.push_back(rpns_mappings_section(sets, label, charts));
  report.sections.push_back(memory_section(sets));
  report.sections.push_back(many_surfaces(sets, label, charts));
  report.sections.push_back(fig8_trimmed_ducks(sets, label, charts));
  report.sections.push_back(accuracy_heatmap(sets, label, charts));
  report.sections.push_back(accuracy_vs_degree(sets, label, charts));
  report.sections.push_back(phases_section(sets, label, charts));
  report.sections.push_back(trim_texture_section(sets, label, charts));
  report.sections.push_back(measurements_section(sets, label));
  // Each chart carries what its caption needs, so the plotter knows nothing about the report.
  for (json& chart : charts["charts"])
    for (const ReportSection& s : report.sections)
      if (s.id == chart["id"]) {
        chart["title"] = s.title;
        chart["context"] = s.context;
        chart["command"] = s.command;
        chart["file"] = s.id + ".png";
      }
  return report;
}

std::string report_markdown(const Report& report) {
  std::string out = "# nurbsbench report\n\n";
  out +=
      "Generated by `nurbsbench report` from the results sets below. Strategies on llvmpipe, "
      "lavapipe or PoCL ran on the CPU: their figures are CPU figures.\n\n";
  for (const ReportSection& s : report.sections) {
    out += fmt::format("## {}\n\n", s.title);
    if (!s.context.empty()) out += fmt::format("*{}*\n\n", s.context);
    if (!s.no_data.empty()) out += fmt::format("**{}**\n\n", s.no_data);
    if (s.has_chart) {
      if (s.chart_note.empty())
        out += fmt::format("![{}]({}.png)\n\n", markdown_cell(s.title), s.id);
      else
        out += fmt::format("> chart {}.png not drawn: {}\n\n", s.id, s.chart_note);
    }
    for (const std::string& image : s.images) out += fmt::format("![{}]({})\n\n", image, image);
    if (!s.command.empty()) out += fmt::format("Regenerate:\n\n```sh\n{}\n```\n\n", s.command);
    for (const ReportTable& t : s.tables) {
      if (!t.caption.empty()) out += fmt::format("{}:\n\n", t.caption);
      std::vector<std::string> header;
      for (const std::string& h : t.header) header.push_back(markdown_cell(h));
      out += fmt::format("| {} |\n|", fmt::join(header, " | "));
      for (std::size_t c = 0; c < t.header.size(); ++c) out += "---|";
      out += "\n";
      for (const auto& row : t.rows) {
        std::vector<std::string> cells;
        for (const std::string& c : row) cells.push_back(markdown_cell(c));
        out += fmt::format("| {} |\n", fmt::join(cells, " | "));
      }
      out += "\n";
    }
    for (const std::string& note : s.notes) out += note + "\n\n";
  }
  return out;
}

std::string report_html(const Report& report) {
  std::string out =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>nurbsbench report</title>\n"
      "<style>body{font-family:sans-serif;max-width:1200px;margin:auto}"
      "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:2px "
      "6px;font-size:90%}th{background:#eee}img{max-width:100%}pre{background:#f4f4f4;padding:"
      "0.5em;white-space:pre-wrap}.context{color:#555;font-style:italic}.nodata{color:#a00}"
      "</style></head><body>\n<h1>nurbsbench report</h1>\n<p>Generated by <code>nurbsbench "
      "report</code>. Strategies on llvmpipe, lavapipe or PoCL ran on the CPU: their figures are "
      "CPU figures.</p>\n";
  for (const ReportSection& s : report.sections) {
    out += fmt::format("<h2 id=\"{}\">{}</h2>\n", s.id, html_escape(s.title));
    if (!s.context.empty())
      out += fmt::format("<p class=\"context\">{}</p>\n", html_escape(s.context));
    if (!s.no_data.empty())
      out += fmt::format("<p class=\"nodata\"><b>{}</b></p>\n", html_escape(s.no_data));
    if (s.has_chart) {
      if (s.chart_note.empty())
        out += fmt::format("<img src=\"{}.png\" alt=\"{}\">\n", s.id, html_escape(s.title));
      else
        out += fmt::format("<p class=\"nodata\">chart {}.png not drawn: {}</p>\n", s.id,
                           html_escape(s.chart_note));
    }
    for (const std::string& image : s.images)
      out += fmt::format("<img src=\"{}\" alt=\"{}\">\n", html_escape(image), html_escape(image));
    if (!s.command.empty())
      out += fmt::format("<p>Regenerate:</p><pre>{}</pre>\n", html_escape(s.command));
    for (const ReportTable& t : s.tables) {
      out += "<table>\n";
      if (!t.caption.empty()) out += fmt::format("<caption>{}</caption>\n", html_escape(t.caption));
      out += "<tr>";
      for (const std::string& h : t.header) out += fmt::format("<th>{}</th>", html_escape(h));
      out += "</tr>\n";
      for (const auto& row : t.rows) {
        out += "<tr>";
        for (const std::string& c : row) out += fmt::format("<td>{}</td>", html_escape(c));
        out += "</tr>\n";
      }
      out += "</table>\n";
    }
    for (const std::string& note : s.notes) out += fmt::format("<p>{}</p>\n", html_escape(note));
  }
  return out + "</body></html>\n";
}

}  // namespace nurbs
