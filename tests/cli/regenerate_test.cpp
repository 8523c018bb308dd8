// Every chart's "regenerate" command (chart_commands() in harness/report.h) is run as declared but
// tiny: the same verb and options, with the scenes, samples, repetitions and frames shrunk by rule
// (so a declared command that stops working breaks this test), then `report` on what it wrote. The
// chart it draws must have the committed chart's structure: kind, axes, series. And each declared
// command must be the one that made the committed data: the settings its results set recorded.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "harness/report.h"
#include "run_cli.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kCommitted = fs::path(NURBSBENCH_SOURCE_DIR) / "results/amd-epyc-2t";

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

// The declared command's words after "nurbsbench", and the value of each option.
std::vector<std::string> words_of(const std::string& run) {
  std::vector<std::string> words = split(run, ' ');
  EXPECT_EQ(words.front(), "nurbsbench") << run;
  words.erase(words.begin());
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

// The tiny variant: the first scene, the smallest grid (at most 32x32: Haar LOD needs three
// halvings), one repetition, two deforming frames; every other word as declared.
std::vector<std::string> tiny(const std::string& run, const std::string& dir) {
  std::vector<std::string> words = words_of(run);
  for (std::size_t i = 0; i + 1 < words.size(); ++i) {
    const std::string& option = words[i];
    std::string& value = words[i + 1];
    if (option == "--scenes") {
      value = split(value, ',').front();
      if (is_scene_alias(value)) value = first_listed_scene();
    } else if (option == "--samples") {
      std::vector<std::string> grids = split(value, ',');
      value = *std::min_element(grids.begin(), grids.end(), [](const auto& a, const auto& b) {
        return grid_points(a) < grid_points(b);
      });
      if (grid_points(value) > 32 * 32) value = "32x32";
    } else if (option == "--repetitions") {
      value = "1";
    } else if (option == "--deforming") {
      value = "2";
    } else if (option == "--out") {
      EXPECT_EQ(value, "DIR") << run;
      value = dir;
    }
  }
  return words;
}

std::set<std::string> labels(const json& chart, const char* list) {
  std::set<std::string> out;
  for (const json& item : chart.value(list, json::array()))
    out.insert(item["label"].get<std::string>());
  return out;
}
std::set<std::string> strings(const json& chart, const char* list) {
  std::set<std::string> out;
  for (const json& item : chart.value(list, json::array())) out.insert(item.get<std::string>());
  return out;
}

// Same kind, fields, axes and series (strategies); the data sizes follow the tiny run's.
void expect_same_structure(const json& made, const json& committed) {
  std::set<std::string> made_keys, committed_keys;
  for (const auto& [key, value] : made.items()) made_keys.insert(key);
  for (const auto& [key, value] : committed.items()) committed_keys.insert(key);
  EXPECT_EQ(made_keys, committed_keys);
  for (const char* key : {"kind", "xlabel", "ylabel", "xlog", "ylog", "colorbar"})
    if (committed.contains(key)) {
      EXPECT_EQ(made[key], committed[key]) << key;
    }
  EXPECT_EQ(labels(made, "series"), labels(committed, "series"));
  EXPECT_EQ(labels(made, "stacks"), labels(committed, "stacks"));
  EXPECT_EQ(strings(made, "rows"), strings(committed, "rows"));
  const std::string kind = committed["kind"];
  if (kind == "stacked") {
    EXPECT_EQ(strings(made, "categories"), strings(committed, "categories"));
  }
  if (kind == "heatmap") {
    const std::set<std::string> cols = strings(committed, "cols");
    for (const std::string& c : strings(made, "cols")) EXPECT_TRUE(cols.contains(c)) << c;
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

json committed_chart(const std::string& id) {
  const json charts = json::parse(read_text(kCommitted / "report/charts.json"));
  for (const json& chart : charts["charts"])
    if (chart["id"] == id) return chart;
  ADD_FAILURE() << "no chart " << id << " in the committed report";
  return json::object();
}

class Regenerate : public ::testing::TestWithParam<ChartCommand> {};

TEST_P(Regenerate, TinyRunDrawsTheCommittedChartsStructure) {
  const ChartCommand& declared = GetParam();
  TempDir tmp;
  const std::string dir = tmp / "results";
  const std::vector<std::string> args = tiny(declared.run, dir);
  const std::string command = fmt::format("nurbsbench {}", fmt::join(args, " "));
  const CliResult made = run_cli(args);
  ASSERT_EQ(made.exit_code, 0) << command << "\n" << made.err;
  const CliResult report = run_cli({"report", "--results", dir, "--out", tmp / "report"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const json charts = json::parse(read_text(tmp.path() / "report/charts.json"));
  const auto it = std::find_if(charts["charts"].begin(), charts["charts"].end(),
                               [&](const json& c) { return c["id"] == declared.id; });
  ASSERT_NE(it, charts["charts"].end()) << declared.id << " not drawn by " << command;
  expect_same_structure(*it, committed_chart(declared.id));
}

// The committed chart says it was regenerated by the declared command, and the results set it
// names recorded that command's scenes, samples, repetitions and frames.
TEST_P(Regenerate, DeclaredCommandMadeTheCommittedData) {
  const ChartCommand& declared = GetParam();
  const std::string command = committed_chart(declared.id).value("command", "");
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
  const fs::path set = fs::path(NURBSBENCH_SOURCE_DIR) / option_value(words, "--out");
  const std::vector<std::string> samples = split(option_value(words, "--samples"), ',');
  if (words.front() == "lod") {
    std::vector<std::string> measured;
    const json lod = json::parse(read_text(set / "lod.json"));
    for (const json& row : lod["rows"]) measured.push_back(row["samples"]);
    EXPECT_EQ(measured, samples);
    return;
  }
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
    if (!is_scene_alias(scene)) {
      EXPECT_NE(std::find(scenes.begin(), scenes.end(), scene), scenes.end()) << scene;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Charts, Regenerate, ::testing::ValuesIn(chart_commands()),
                         [](const auto& info) { return info.param.id; });

}  // namespace
}  // namespace nurbs::test
