// Every chart's "regenerate" command (chart_commands(), the chart rows of
// harness/report/sections.cpp) is run as declared but tiny: the same verb (or script) and options,
// with every list cut to its first item (the grids to the smallest), one repetition and two
// deforming frames (so a declared command that stops working breaks this test), then `report` on
// what it wrote. The chart it draws must have the committed chart's structure: kind, axes, series.
// And each declared command must be the one that made the committed data: the settings its results
// sets recorded.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "harness/report/report.h"
#include "run_cli.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kCommitted = fs::path(NURBSBENCH_SOURCE_DIR) / "results/canonical";

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(separator, start), text.size());
    parts.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return parts;
}

// A command's words: the program ("nurbsbench" or a script of scripts/), then its arguments.
std::vector<std::string> words_of(const std::string& run) {
  std::vector<std::string> words = split(run, ' ');
  EXPECT_TRUE(words.front() == "nurbsbench" || words.front().starts_with("scripts/")) << run;
  return words;
}
std::string option_value(const std::vector<std::string>& words, const std::string& option) {
  const auto it = std::find(words.begin(), words.end(), option);
  return it == words.end() || it + 1 == words.end() ? "" : *(it + 1);
}

long long grid_points(const std::string& grid) {
  const std::size_t x = grid.find('x');
  return std::stoll(grid.substr(0, x)) * std::stoll(grid.substr(x + 1));
}

// A scene list names scenes or an alias of the CLI ("all", "default"), which the tiny run replaces
// by the first scene `nurbsbench list` gives.
bool is_scene_alias(const std::string& name) {
  static const std::set<std::string> scenes = [] {
    const CliResult r = run_cli({"list", "--json"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    // Named: a range-for over a temporary's ["scenes"] would outlive the parsed document.
    const json listed = json::parse(r.out);
    std::set<std::string> names;
    for (const json& s : listed["scenes"]) names.insert(s["name"].get<std::string>());
    return names;
  }();
  return !scenes.contains(name);
}
std::string first_listed_scene() {
  const CliResult r = run_cli({"list", "--json"});
  return json::parse(r.out)["scenes"][0]["name"].get<std::string>();
}

// The tiny variant: the first item of every list (scenes, ...; the first two resolutions), the
// smallest grid (at most 32x32: Haar LOD needs three halvings), one repetition, two deforming or
// camera-path frames; every other word as declared. A script is given the binary under test.
std::vector<std::string> tiny(const std::string& run, const std::string& dir) {
  std::vector<std::string> words = words_of(run);
  for (std::size_t i = 1; i + 1 < words.size(); ++i) {
    const std::string& option = words[i];
    std::string& value = words[i + 1];
    if (option == "--scenes") {
      value = split(value, ',').front();
      if (is_scene_alias(value)) value = first_listed_scene();
    } else if (option == "--resolutions" || option == "--modes") {
      // A resolution curve needs two points (the report draws no one-point curve); a comparison
      // of vk-ksquad's mappings, two mappings.
      const std::vector<std::string> items = split(value, ',');
      value = items.size() > 1 ? items[0] + "," + items[1] : items[0];
    } else if (option.starts_with("--") && option != "--samples" &&
               value.find(',') != std::string::npos) {
      value = split(value, ',').front();
    } else if (option == "--samples") {
      std::vector<std::string> grids = split(value, ',');
      value = *std::min_element(grids.begin(), grids.end(), [](const auto& a, const auto& b) {
        return grid_points(a) < grid_points(b);
      });
      if (grid_points(value) > 32 * 32) value = "32x32";
    } else if (option == "--repetitions") {
      value = "1";
    } else if (option == "--deforming" || option == "--frames") {
      value = "2";
    } else if (option == "--out") {
      EXPECT_EQ(value, "DIR") << run;
      value = dir;
    }
  }
  if (words.front() != "nurbsbench") words.insert(words.end(), {"--nurbsbench", NURBSBENCH_CLI});
  return words;
}

std::string shell_quote(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// Runs the tiny command and, for a verb, `report` on what it wrote; returns the charts.json made
// (a script writes its own report, in DIR/report).
json run_tiny(const std::string& declared, const TempDir& tmp) {
  const std::string dir = tmp / "results";
  std::vector<std::string> args = tiny(declared, dir);
  std::string command;
  for (const std::string& a : args) {
    if (!command.empty()) command += ' ';
    command += shell_quote(a);
  }
  if (args.front() != "nurbsbench") {
    const int status =
        std::system(fmt::format("cd {} && bash {} > {} 2>&1", shell_quote(NURBSBENCH_SOURCE_DIR),
                                command, shell_quote(tmp / "script.log"))
                        .c_str());
    EXPECT_EQ(status, 0) << command << "\n" << read_text(tmp.path() / "script.log");
    return json::parse(read_text(fs::path(dir) / "report/charts.json"));
  }
  args.erase(args.begin());
  const CliResult made = run_cli(args);
  EXPECT_EQ(made.exit_code, 0) << command << "\n" << made.err;
  const CliResult report = run_cli({"report", "--results", dir, "--out", tmp / "report"});
  EXPECT_EQ(report.exit_code, 0) << report.err;
  return json::parse(read_text(tmp.path() / "report/charts.json"));
}

// A report of sets from several commits tags each label with its set ("cl-stair [fig7-...]"); the
// tiny run is one set, so labels are compared without the tag.
std::string untagged(std::string label) {
  if (label.ends_with(']'))
    if (const auto open = label.rfind(" ["); open != std::string::npos) label.erase(open);
  return label;
}

std::set<std::string> labels(const json& chart, const char* list) {
  std::set<std::string> out;
  for (const json& item : chart.value(list, json::array()))
    out.insert(untagged(item["label"].get<std::string>()));
  return out;
}
std::set<std::string> strings(const json& chart, const char* list) {
  std::set<std::string> out;
  for (const json& item : chart.value(list, json::array()))
    out.insert(untagged(item.get<std::string>()));
  return out;
}

// Same kind, fields, axes and series (strategies); the data sizes follow the tiny run's.
// Every series and row label of every committed chart (untagged): the strategies the committed
// results measured.
std::set<std::string> committed_names();

// A label the tiny run draws that no committed chart knows anywhere is a strategy added since
// results/canonical was measured (scripts/canonical.sh measures it): allowed, and said. A label
// the committed set knows must be in this chart (a chart that lost a strategy fails).
bool newer_than_committed(const std::string& label) {
  static const std::set<std::string> known = committed_names();
  if (known.contains(label)) return false;
  std::cout << "note: '" << label
            << "' is not in the committed results (newer than results/canonical)\n";
  return true;
}

void expect_same_structure(const json& made, const json& committed) {
  std::set<std::string> made_keys, committed_keys;
  for (const auto& [key, value] : made.items()) made_keys.insert(key);
  for (const auto& [key, value] : committed.items()) committed_keys.insert(key);
  EXPECT_EQ(made_keys, committed_keys);
  for (const char* key : {"kind", "xlabel", "ylabel", "xlog", "ylog", "colorbar"})
    if (committed.contains(key)) {
      EXPECT_EQ(made[key], committed[key]) << key;
    }
  // Series: a subset (the tiny run has one scene, tolerance, ...), never empty, never a new name.
  const std::set<std::string> series = labels(committed, "series");
  for (const std::string& l : labels(made, "series"))
    EXPECT_TRUE(series.contains(l) || newer_than_committed(l)) << l;
  EXPECT_EQ(labels(made, "series").empty(), series.empty());
  EXPECT_EQ(labels(made, "stacks"), labels(committed, "stacks"));
  // Rows (strategies): a subset too -- the tiny run's one scene can be one a strategy refuses
  // (the T-spline strategies on a NURBS scene) -- never a new name.
  const std::set<std::string> rows = strings(committed, "rows");
  for (const std::string& r : strings(made, "rows"))
    EXPECT_TRUE(rows.contains(r) || newer_than_committed(r)) << r;
  EXPECT_EQ(strings(made, "rows").empty(), rows.empty());
  const std::string kind = committed["kind"];
  if (kind == "stacked") {
    // The same categories (strategies), less those newer than the committed results.
    const std::set<std::string> committed_categories = strings(committed, "categories");
    std::set<std::string> made_categories = strings(made, "categories");
    std::erase_if(made_categories, [&](const std::string& c) {
      return !committed_categories.contains(c) && newer_than_committed(c);
    });
    EXPECT_EQ(made_categories, committed_categories);
  }
  if (kind == "heatmap") {
    const std::set<std::string> cols = strings(committed, "cols");
    for (const std::string& c : strings(made, "cols"))
      EXPECT_TRUE(cols.contains(c) || newer_than_committed(c)) << c;
  }
  for (const json& s : made.value("series", json::array())) {
    if (kind == "lines") {
      EXPECT_EQ(s["x"].size(), s["y"].size()) << s["label"];
      EXPECT_FALSE(s["x"].empty()) << s["label"];
    } else {
      EXPECT_EQ(s["values"].size(), made["categories"].size()) << s["label"];
    }
  }
}

// In the machine's report, or in the report a study script wrote beside its results.
json committed_chart(const std::string& id) {
  std::vector<fs::path> files{kCommitted / "report/charts.json"};
  for (const auto& entry : fs::recursive_directory_iterator(kCommitted))
    if (entry.path().filename() == "charts.json") files.push_back(entry.path());
  for (const fs::path& file : files) {
    const json charts = json::parse(read_text(file));
    for (const json& chart : charts["charts"])
      if (chart["id"] == id) return chart;
  }
  ADD_FAILURE() << "no chart " << id << " in the committed reports";
  return json::object();
}

std::set<std::string> committed_names() {
  std::set<std::string> names;
  for (const auto& entry : fs::recursive_directory_iterator(kCommitted)) {
    if (entry.path().filename() != "charts.json") continue;
    for (const json& chart : json::parse(read_text(entry.path()))["charts"]) {
      for (const char* list : {"series", "stacks"}) names.merge(labels(chart, list));
      names.merge(strings(chart, "rows"));
      if (chart["kind"] == "heatmap") names.merge(strings(chart, "cols"));
      if (chart["kind"] == "stacked") names.merge(strings(chart, "categories"));
    }
  }
  return names;
}

class Regenerate : public ::testing::TestWithParam<ChartCommand> {};

TEST_P(Regenerate, TinyRunDrawsTheCommittedChartsStructure) {
  const ChartCommand& declared = GetParam();
  TempDir tmp;
  const json charts = run_tiny(declared.run, tmp);
  const auto it = std::find_if(charts["charts"].begin(), charts["charts"].end(),
                               [&](const json& c) { return c["id"] == declared.id; });
  ASSERT_NE(it, charts["charts"].end()) << declared.id << " not drawn by its tiny command";
  expect_same_structure(*it, committed_chart(declared.id));
}

// The committed chart says it was regenerated by the declared command, and the results set it
// names recorded that command's scenes, samples, repetitions and frames.
TEST_P(Regenerate, DeclaredCommandMadeTheCommittedData) {
  const ChartCommand& declared = GetParam();
  const std::string command = committed_chart(declared.id).value("command", "");
  // A chart added since results/canonical was made: scripts/canonical.sh makes it.
  ASSERT_FALSE(command.empty()) << declared.id << ": no committed command";
  const std::vector<std::string> words = words_of(command.substr(0, command.find(" && ")));
  // The verb and every option declared (a section may add one: phases names its precision).
  const std::vector<std::string> wanted = words_of(declared.run);
  EXPECT_EQ(words.front(), wanted.front()) << command;
  for (const std::string& word : wanted) {
    if (word.starts_with("--")) {
      EXPECT_NE(std::find(words.begin(), words.end(), word), words.end())
          << word << ": " << command;
    }
  }
  // The same values, but for where it wrote and the grid a section may pick (phases shows one;
  // the grids are checked against the results below).
  for (std::size_t i = 1; i + 1 < wanted.size(); ++i) {
    if (wanted[i].starts_with("--") && wanted[i] != "--out" && wanted[i] != "--samples") {
      EXPECT_EQ(option_value(words, wanted[i]), wanted[i + 1]) << wanted[i] << ": " << command;
    }
  }
  const fs::path out = fs::path(NURBSBENCH_SOURCE_DIR) / option_value(words, "--out");
  const std::vector<std::string> samples = split(option_value(words, "--samples"), ',');
  if (words[1] == "camera-path") {
    const json settings = json::parse(read_text(out / "camera_path.json"))["settings"];
    EXPECT_EQ(settings["scenes"], option_value(words, "--scenes"));
    EXPECT_EQ(std::to_string(settings["frames"].get<int>()), option_value(words, "--frames"));
    EXPECT_EQ(settings["viewport"], option_value(words, "--viewport"));
    EXPECT_EQ(settings["fixed_samples"], option_value(words, "--fixed-samples"));
    EXPECT_EQ(settings["pixels_per_sample"].get<double>(),
              std::stod(option_value(words, "--pixels-per-sample")));
    return;
  }
  if (words[1] == "lod") {
    std::vector<std::string> measured;
    const json lod = json::parse(read_text(out / "lod.json"));
    for (const json& row : lod["rows"]) measured.push_back(row["samples"]);
    EXPECT_EQ(measured, samples);
    return;
  }
  // A verb wrote one results set in DIR; a study script one per configuration below it.
  std::vector<fs::path> sets;
  if (fs::exists(out / "results.json")) sets.push_back(out);
  for (const auto& entry : fs::directory_iterator(out))
    if (fs::exists(entry.path() / "results.json")) sets.push_back(entry.path());
  ASSERT_FALSE(sets.empty()) << out;
  for (const fs::path& set : sets) {
    SCOPED_TRACE(set.string());
    const json settings = json::parse(read_text(set / "results.json"))["settings"];
    // Every grid the command names was measured (phases names the one it shows).
    const auto samplings = settings["samplings"].get<std::vector<std::string>>();
    for (const std::string& grid : samples) {
      EXPECT_NE(std::find(samplings.begin(), samplings.end(), grid), samplings.end()) << grid;
    }
    EXPECT_EQ(std::to_string(settings["repetitions"].get<int>()),
              option_value(words, "--repetitions"));
    const std::string frames = option_value(words, "--deforming");
    EXPECT_EQ(settings["deforming_frames"].get<int>(), frames.empty() ? 0 : std::stoi(frames));
    const auto scenes = settings["scenes"].get<std::vector<std::string>>();
    for (const std::string& scene : split(option_value(words, "--scenes"), ',')) {
      if (!scene.empty() && !is_scene_alias(scene)) {
        EXPECT_NE(std::find(scenes.begin(), scenes.end(), scene), scenes.end()) << scene;
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Charts, Regenerate, ::testing::ValuesIn(chart_commands()),
                         [](const auto& info) { return info.param.id; });

}  // namespace
}  // namespace nurbs::test
