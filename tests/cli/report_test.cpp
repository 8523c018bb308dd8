// The tooling verbs that read results: report (REPORT.md, index.html, charts), recommend,
// gbench-json; and eval's error heat maps. Results are made by `nurbsbench run` on tiny grids or
// written by hand (synthetic records with a known answer).
#include "harness/report/report.h"

#include <OpenImageIO/imageio.h>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "harness/error_image.h"
#include "harness/results_writer.h"
#include "reference/reference_evaluator.h"
#include "run_cli.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

void expect_usage_error(const CliResult& r, const std::vector<std::string>& substrings) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(is_one_error_line(r.err)) << "stderr:\n" << r.err;
  for (const std::string& s : substrings)
    EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

bool matplotlib_present() {
  return std::system("/usr/bin/python3 -c 'import matplotlib' > /dev/null 2>&1") == 0;
}

// A record written by hand: patch144 at 256x256, f32, with the given throughput and error.
Record synthetic(const std::string& strategy, double points_per_s, double max_ulp,
                 Status status = Status::ok) {
  Record r;
  r.scene = "patch144";
  r.strategy = strategy;
  r.role = "strategy";
  r.device = {"host CPU", "cpu", {}};
  r.precision = "f32";
  r.sampling = "grid";
  r.samples = "256x256";
  r.points = 65536;
  r.repetitions = 3;
  if (points_per_s > 0) {
    r.evaluate = {0.9 * 65536 / points_per_s, 65536 / points_per_s, 1.1 * 65536 / points_per_s};
    r.end_to_end = {0, 2 * 65536 / points_per_s, 0};
  }
  r.throughput_pts_per_s = points_per_s;
  r.status = status;
  if (status == Status::ok) {
    Accuracy a;
    a.max_ulp = max_ulp;
    a.max_abs = max_ulp * 1e-7;
    r.accuracy = a;
  } else {
    r.reason = "device lost";
  }
  return r;
}

// ------------------------------------------------------------------------------------- report

class CliReport : public ::testing::Test {
 protected:
  // One tiny run with every strategy (and the store-limit row) on the scenes the charts read.
  // Made once per build and shared by every case (each runs in a process of its own).
  static void SetUpTestSuite() {
    const SharedCliOutput run =
        shared_cli_output({"run", "--scenes", "patch144,tan16,many-1,many-4,degree-2",
                           "--strategies", "all", "--samples", "4x4,8x8", "--repetitions", "1"});
    ASSERT_EQ(run.result.exit_code, 0) << run.result.err;
    results_ = run.directory;
  }
  static std::set<std::string> strategies_in_results() {
    std::set<std::string> names;
    // Named, not iterated as a temporary: a range-for over `parse(...)["records"]` would outlive
    // the parsed document (the heap-use-after-free that ASan aborted this suite on).
    const json results = json::parse(read_text(results_ / "results.json"));
    for (const json& r : results["records"]) names.insert(r["strategy"].get<std::string>());
    return names;
  }
  // A copy of the run's results in a fresh directory, where side files can be added.
  std::string copy_results(const std::string& name) {
    const fs::path dir = tmp_.path() / name;
    fs::create_directories(dir);
    fs::copy_file(results_ / "results.json", dir / "results.json");
    return dir.string();
  }

  static std::filesystem::path results_;
  TempDir tmp_;
};
std::filesystem::path CliReport::results_;

TEST_F(CliReport, WritesTablesChartsAndHtmlListingEveryStrategy) {
  const std::string out = tmp_ / "report";
  const CliResult r =
      run_cli({"report", "--results", results_.string(), "--out", out, "--error-images", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = read_text(fs::path(out) / "REPORT.md");
  const std::string html = read_text(fs::path(out) / "index.html");
  for (const std::string& name : strategies_in_results()) {
    EXPECT_NE(md.find(name), std::string::npos) << name;
    EXPECT_NE(html.find(name), std::string::npos) << name;
  }
  EXPECT_EQ(lower(md).find("nan"), std::string::npos);
  EXPECT_EQ(lower(html).find("nan"), std::string::npos);
  // Every chart titled with its paper figure; the machine and the command under it.
  for (const char* title : {"Krishnamurthy 2007 Fig 7", "Tan 2012 Fig 14", "Tan 2012 Fig 15",
                            "Fig 8 style", "max_ulp vs degree", "Phase breakdown"})
    EXPECT_NE(md.find(title), std::string::npos) << title;
  EXPECT_NE(md.find("Machine: "), std::string::npos);
  EXPECT_NE(md.find("nurbsbench report --results"), std::string::npos);
  EXPECT_NE(md.find("of store limit"), std::string::npos);
  // 4x4 and 8x8 write far under kStoreLimitMinBytes: the limit rows exist, their fraction is
  // withheld and the footnote says why.
  EXPECT_NE(md.find("| —† |"), std::string::npos) << md;
  EXPECT_NE(md.find("—†: the limit row's output is under 1024 KiB"), std::string::npos);
  // Where the run could copy on a Vulkan device, the table has the device-copy column and says
  // what it is; where it could not, neither appears.
  bool copied = false;
  const json results = json::parse(read_text(results_ / "results.json"));
  for (const json& rec : results["records"])
    copied = copied || (rec["strategy"] == "limit-device-copy" && rec["status"] == "ok");
  EXPECT_EQ(md.find("| of device copy |") != std::string::npos, copied) << md;
  EXPECT_EQ(md.find("of device copy = the strategy's points/s") != std::string::npos, copied);
  // Absent side data says what to run instead of failing.
  EXPECT_NE(md.find("no data in these results: run nurbsbench lod"), std::string::npos);
  EXPECT_NE(md.find("no data in these results: run nurbsbench memory"), std::string::npos);
  for (const ChartCommand& c : chart_commands()) {
    if (c.id == "rpns_frame") {
      EXPECT_NE(md.find("no data in these results: run " + c.run.substr(0, c.run.size() - 3)),
                std::string::npos);
    }
  }
  const json charts = json::parse(read_text(fs::path(out) / "charts.json"));
  ASSERT_GE(charts["charts"].size(), 6u);
  if (matplotlib_present()) {
    for (const json& chart : charts["charts"]) {
      const fs::path png = fs::path(out) / chart["file"].get<std::string>();
      EXPECT_TRUE(fs::exists(png) && fs::file_size(png) > 1000) << png;
      EXPECT_NE(md.find("](" + chart["file"].get<std::string>() + ")"), std::string::npos);
    }
  }
  // The worst pair's error heat map, re-evaluated here.
  EXPECT_NE(md.find("![error-"), std::string::npos) << md;
}

// The HTML report as a reader opens it: headless Chromium (Debian's `chromium`, installed by
// scripts/setup.sh --tests) loads index.html; a script appended to a copy of it counts, once the
// page has loaded, the <img> elements and those that failed (naturalWidth 0) into the title, which
// --dump-dom prints; a second run takes the screenshot. Every chart image must load.
TEST_F(CliReport, OpensInAHeadlessBrowserWithEveryChartImageLoaded) {
  const fs::path chromium = "/usr/bin/chromium";
  if (!fs::exists(chromium)) {
    if (std::getenv("NURBSBENCH_REQUIRE_ALL_STRATEGIES"))
      FAIL() << "chromium is missing (scripts/setup.sh --tests installs it)";
    GTEST_SKIP() << "chromium is not installed (scripts/setup.sh --tests)";
  }
  if (!matplotlib_present()) GTEST_SKIP() << "no matplotlib: the report has no chart images";
  const fs::path out = tmp_ / "report";
  ASSERT_EQ(run_cli({"report", "--results", results_.string(), "--out", out.string(),
                     "--error-images", "0"})
                .exit_code,
            0);
  const std::string html = read_text(out / "index.html");
  const std::size_t charts = json::parse(read_text(out / "charts.json"))["charts"].size();
  std::string checked = html;
  checked.insert(checked.rfind("</body>"), R"(<script>
window.addEventListener('load', () => {
  const images = Array.from(document.images);
  const broken = images.filter(i => !i.complete || i.naturalWidth === 0).map(i => i.src);
  document.title = 'images=' + images.length + ' broken=' + broken.length + ' ' + broken.join(' ');
});
</script>
)");
  { std::ofstream(out / "checked.html") << checked; }
  const std::string url = "file://" + (out / "checked.html").string();
  const std::string flags =
      "--headless --no-sandbox --disable-gpu --allow-file-access-from-files "
      "--virtual-time-budget=10000 --window-size=1280,2000";
  const fs::path dom = out / "dom.html", log = out / "chromium.log";
  ASSERT_EQ(std::system(fmt::format("{} {} --dump-dom '{}' > '{}' 2> '{}'", chromium.string(),
                                    flags, url, dom.string(), log.string())
                            .c_str()),
            0)
      << read_text(log);
  const std::string dumped = read_text(dom);
  const std::size_t title = dumped.find("<title>images=");
  ASSERT_NE(title, std::string::npos) << "the check script did not run:\n" << read_text(log);
  const std::string result = dumped.substr(title + 7, dumped.find("</title>", title) - title - 7);
  EXPECT_EQ(result, fmt::format("images={} broken=0 ", charts)) << result;

  const fs::path screenshot = out / "screenshot.png";
  ASSERT_EQ(std::system(fmt::format("cd '{}' && {} {} --screenshot='{}' '{}' > '{}' 2>&1",
                                    out.string(), chromium.string(), flags, screenshot.string(),
                                    "file://" + (out / "index.html").string(), log.string())
                            .c_str()),
            0)
      << read_text(log);
  auto image = OIIO::ImageInput::open(screenshot.string());
  ASSERT_TRUE(image) << "no screenshot: " << read_text(log);
  EXPECT_EQ(image->spec().width, 1280);
  EXPECT_EQ(image->spec().height, 2000);
}

TEST_F(CliReport, WithoutMatplotlibWritesTablesAndSaysWhichChartsAreMissing) {
  const std::string fake_python = tmp_ / "python-without-matplotlib";
  write_text(fake_python,
             "#!/bin/sh\necho \"matplotlib missing: ModuleNotFoundError: No module named "
             "'matplotlib'\"\nexit 3\n");
  fs::permissions(fake_python, fs::perms::owner_all);
  const std::string out = tmp_ / "report";
  const CliResult r = run_cli({"report", "--results", results_.string(), "--out", out,
                               "--error-images", "0", "--python", fake_python});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = read_text(fs::path(out) / "REPORT.md");
  EXPECT_NE(md.find("> chart fig7_time_vs_points.png not drawn: matplotlib missing"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| patch144 |"), std::string::npos) << "tables are still written";
  EXPECT_FALSE(fs::exists(fs::path(out) / "fig7_time_vs_points.png"));

  const CliResult no_python =
      run_cli({"report", "--results", results_.string(), "--out", tmp_ / "report2",
               "--error-images", "0", "--python", tmp_ / "no-such-python"});
  ASSERT_EQ(no_python.exit_code, 0) << no_python.err;
  EXPECT_NE(read_text(fs::path(tmp_ / "report2") / "REPORT.md").find("not drawn: cannot run"),
            std::string::npos);
}

// The first screen: the verdicts, then the charts; the sets and strategies tables after them.
TEST_F(CliReport, OpensWithTheClaimsAndChartsAndEndsWithTheBookkeeping) {
  const Report report = build_report({load_result_set(results_)});
  ASSERT_FALSE(report.sections.empty());
  EXPECT_EQ(report.sections.front().id, "claims");
  const auto results = std::find_if(report.sections.begin(), report.sections.end(),
                                    [](const ReportSection& s) { return s.id == "results"; });
  ASSERT_NE(results, report.sections.end());
  for (auto it = results; it != report.sections.end(); ++it)
    EXPECT_FALSE(it->has_chart) << it->id << " comes after the bookkeeping";
  const std::string md = report_markdown(report);
  EXPECT_LT(md.find("## Paper vs measured"), md.find("## Krishnamurthy 2007 Fig 7"));
  EXPECT_LT(md.find("## Krishnamurthy 2007 Fig 7"), md.find("## Results sets and strategies"));
}

// A strategy refused on many scenes for one cause reads as one line with the number of scenes
// (counted here from results.json), not one sentence per scene; the scenes are listed in a table
// of their own.
TEST_F(CliReport, GroupsRefusalsByReasonWithASceneCount) {
  const json results = json::parse(read_text(results_ / "results.json"));
  std::map<std::string, std::set<std::string>> refused;  // strategy -> scenes it refused
  for (const json& r : results["records"])
    if (r["status"] == "refused")
      refused[r["strategy"].get<std::string>()].insert(r["scene"].get<std::string>());
  // cpu-tspline evaluates T-splines only and these scenes are all NURBS.
  ASSERT_TRUE(refused.contains("cpu-tspline"));
  const Report report = build_report({load_result_set(results_)});
  const auto section = std::find_if(report.sections.begin(), report.sections.end(),
                                    [](const ReportSection& s) { return s.id == "results"; });
  ASSERT_NE(section, report.sections.end());
  const ReportTable* strategies = nullptr;
  const ReportTable* scenes = nullptr;
  for (const ReportTable& t : section->tables) {
    if (t.caption == "Every strategy in these results") strategies = &t;
    if (t.caption == "Scenes not measured, by strategy and reason") scenes = &t;
  }
  ASSERT_NE(strategies, nullptr);
  ASSERT_NE(scenes, nullptr);
  bool seen = false;
  for (const auto& row : strategies->rows) {
    ASSERT_EQ(row.size(), 5u);
    EXPECT_EQ(row[4].find("surface '"), std::string::npos) << row[0] << ": " << row[4];
    if (row[0] != "cpu-tspline") continue;
    seen = true;
    const std::size_t n = refused.at("cpu-tspline").size();
    EXPECT_EQ(row[4],
              fmt::format("refused on {} scene{}: NURBS surface, the strategy evaluates T-splines "
                          "only",
                          n, n == 1 ? "" : "s"));
  }
  EXPECT_TRUE(seen);
  // Every refused (strategy, scene) appears in the scenes table.
  for (const auto& [strategy, names] : refused)
    for (const std::string& scene : names)
      EXPECT_TRUE(std::any_of(scenes->rows.begin(), scenes->rows.end(),
                              [&](const std::vector<std::string>& row) {
                                return row[0] == strategy &&
                                       (", " + row[2] + ",").find(", " + scene + ",") !=
                                           std::string::npos;
                              }))
          << strategy << " on " << scene;
}

// The memory section's regenerate command as sections.cpp states it: `memory --json` into a
// directory of its own, then report on that directory, which holds no results.json.
TEST_F(CliReport, MemoryFileAloneIsAResultsSet) {
  const fs::path dir = tmp_ / "memory-alone";
  fs::create_directories(dir);
  const CliResult memory = run_cli({"memory", "--scenes", "teapot", "--json"});
  ASSERT_EQ(memory.exit_code, 0) << memory.err;
  write_text(dir / "memory.json", memory.out);
  const std::string out = tmp_ / "report";
  const CliResult r =
      run_cli({"report", "--results", dir.string(), "--out", out, "--error-images", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = read_text(fs::path(out) / "REPORT.md");
  EXPECT_NE(md.find("Control-point memory (from memory.json)"), std::string::npos) << md;
  EXPECT_NE(md.find("| teapot | 32 |"), std::string::npos) << md;
}

// A folder of sets (what scripts/canonical.sh writes): every set below it, side files in folders
// of their own included; a report folder inside is not a set. A folder with nothing in or below
// it is still bad input naming its missing results.json.
TEST_F(CliReport, FolderOfSetsIsEverySetBelowIt) {
  const fs::path tree = tmp_ / "tree";
  for (const char* set : {"fig7", "nested/second"}) {
    fs::create_directories(tree / set);
    fs::copy_file(results_ / "results.json", tree / set / "results.json");
  }
  fs::create_directories(tree / "memory");
  const CliResult memory = run_cli({"memory", "--scenes", "teapot", "--json"});
  ASSERT_EQ(memory.exit_code, 0) << memory.err;
  write_text(tree / "memory" / "memory.json", memory.out);
  fs::create_directories(tree / "report");
  write_text(tree / "report" / "charts.json", "{}");
  const CliResult r = run_cli({"report", "--results", tree.string(), "--error-images", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = read_text(tree / "report" / "REPORT.md");
  EXPECT_NE(md.find("| fig7 ["), std::string::npos) << md;
  EXPECT_NE(md.find("| second ["), std::string::npos) << md;
  EXPECT_NE(md.find("| teapot | 32 |"), std::string::npos) << md;
  const fs::path empty = tmp_ / "empty-tree";
  fs::create_directories(empty / "sub");
  expect_usage_error(run_cli({"report", "--results", empty.string(), "--out", tmp_ / "r2"}),
                     {"empty-tree", "results.json"});
}

TEST_F(CliReport, ReadsLodAndMemoryFilesBesideTheResults) {
  const std::string dir = copy_results("with-side-files");
  write_text(fs::path(dir) / "lod.json", R"JSON({"format": "nurbsbench-lod/1",
    "machine": {"cpu_model": "Test CPU", "git_commit": "abc123"}, "settings": {},
    "rows": [{"scene": "tan21x23", "samples": "128x128",
              "device": {"name": "llvmpipe (LLVM 15)", "kind": "cpu"},
              "coarser_by_haar_s": 0.001, "coarser_by_reevaluation_s": 0.004,
              "finer_by_haar_s": 0.002, "finer_by_reevaluation_s": 0.005,
              "levels": [{"level": 1, "samples": "64x64", "max_distance": 1e-6, "max_ulp": 3.5}]}]})JSON");
  write_text(fs::path(dir) / "memory.json", R"({"format": "nurbsbench-memory/1", "rows": [
    {"scene": "teapot", "surfaces": 32, "nurbs_control_points": 512, "nurbs_bytes": 16384,
     "bezier_patches": 32, "bezier_control_points": 512, "bezier_bytes": 32768, "ksquads": 32,
     "bezier_shared_control_points": 512, "bezier_shared_bytes": 8192},
    {"scene": "older", "surfaces": 1, "nurbs_control_points": 16, "nurbs_bytes": 256,
     "bezier_patches": 1, "bezier_control_points": 16, "bezier_bytes": 256, "ksquads": 1}]})");
  const std::string out = tmp_ / "report";
  const CliResult r = run_cli({"report", "--results", dir, "--out", out, "--error-images", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = read_text(fs::path(out) / "REPORT.md");
  // A lod.json from before the full baseline and the draws were measured: those read "n/a".
  EXPECT_NE(md.find("| tan21x23 | 128x128 | llvmpipe (LLVM 15) (a CPU implementation of the API, "
                    "not a GPU) | 1 ms | 4 ms | n/a | 4 | n/a | 2 ms | 5 ms | n/a | 2.5 | n/a |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| tan21x23 | 128x128 | 1 | 64x64 | 1e-06 | 3.5 | n/a | n/a | n/a |"),
            std::string::npos);
  EXPECT_NE(md.find("| teapot | 32 | 512 | 16384 | 32 | 512 | 32768 | 2 | 32 | 512 | 8192 | 0.5 |"),
            std::string::npos)
      << md;
  // A memory.json from before the shared-once count: that reading is absent, not zero.
  EXPECT_NE(md.find("| older | 1 | 16 | 256 | 1 | 16 | 256 | 1 | 1 | n/a | n/a | n/a |"),
            std::string::npos);
  EXPECT_EQ(md.find("no data in these results: run nurbsbench lod"), std::string::npos);
  EXPECT_EQ(lower(md).find("nan"), std::string::npos);
}

// A lod.json with 002's full baseline and each level's draw: both shown, the level-0 draw as a row
// of its own, and the Fig 15 claim taken against the full baseline.
TEST_F(CliReport, ShowsLodFullBaselineAndLevelDraws) {
  const std::string dir = tmp_ / "lod-only";
  fs::create_directories(dir);
  write_text(fs::path(dir) / "lod.json", R"JSON({"format": "nurbsbench-lod/1",
    "machine": {"cpu_model": "Test CPU", "git_commit": "abc123"}, "settings": {},
    "rows": [{"scene": "tan21x23", "samples": "128x128",
              "device": {"name": "llvmpipe (LLVM 15)", "kind": "cpu"},
              "coarser_by_haar_s": 0.001, "coarser_by_reevaluation_s": 0.002,
              "coarser_by_full_reevaluation_s": 0.005, "coarser_index_elements": 23814,
              "finer_by_haar_s": 0.002, "finer_by_reevaluation_s": 0.004,
              "finer_by_full_reevaluation_s": 0.008, "finer_index_elements": 96774,
              "render_s": 0.016, "index_elements": 96774, "drawn_pixels": 196333,
              "levels": [{"level": 1, "samples": "64x64", "max_distance": 1e-6, "max_ulp": 3.5,
                          "render_s": 0.006, "index_elements": 23814,
                          "drawn_pixels": 188671}]}]})JSON");
  const std::string out = tmp_ / "lod-report";
  const CliResult r = run_cli({"report", "--results", dir, "--out", out, "--error-images", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = read_text(fs::path(out) / "REPORT.md");
  EXPECT_NE(md.find("| 1 ms | 2 ms | 5 ms | 2 | 5 | 2 ms | 4 ms | 8 ms | 2 | 4 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| tan21x23 | 128x128 | 0 | 128x128 | n/a | n/a | 16 ms | 96774 | 196333 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| tan21x23 | 128x128 | 1 | 64x64 | 1e-06 | 3.5 | 6 ms | 23814 | 188671 |"),
            std::string::npos)
      << md;
  // The paper's comparison keeps both sides on the device: 2x, within 2x of its 3-5x. Through the
  // host (the full baseline, a second line): 5x, 4x.
  EXPECT_NE(md.find("re-evaluation on the device 2 ms / Haar 1 ms = 2×"), std::string::npos) << md;
  EXPECT_NE(md.find("| holds within 2× |"), std::string::npos) << md;
  EXPECT_NE(md.find("full re-evaluation 5 ms / Haar 1 ms = 5×"), std::string::npos) << md;
  EXPECT_NE(md.find("full re-evaluation 8 ms / Haar 2 ms = 4×"), std::string::npos) << md;
}

// A lod.json written before the full baseline and the draws were measured (nurbsbench-lod/1, the
// canonical results' file as it was: tests/data/lod_v1_without_full_baseline.json) still reads,
// its new columns "n/a".
TEST_F(CliReport, ReadsTheCommittedLodFileWithoutTheNewColumns) {
  const std::string dir = tmp_ / "committed-lod";
  fs::create_directories(dir);
  fs::copy_file(fs::path(NURBSBENCH_TEST_DATA) / "lod_v1_without_full_baseline.json",
                fs::path(dir) / "lod.json");
  const std::string out = tmp_ / "committed-lod-report";
  const CliResult r = run_cli({"report", "--results", dir, "--out", out, "--error-images", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = read_text(fs::path(out) / "REPORT.md");
  EXPECT_NE(md.find("not a GPU) | 283 us | 1.26 ms | n/a | 4.46 | n/a | 366 us | 2.79 ms | n/a | "
                    "7.62 | n/a |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| tan21x23 | 128x128 | 1 | 64x64 | 0.00787 | 6.47e+03 | n/a | n/a | n/a |"),
            std::string::npos)
      << md;
}

TEST_F(CliReport, ShowsDeformingFramesFromRecordsWithAFramePhase) {
  ResultsFile results = read_results(results_);
  const std::string dir = tmp_ / "deforming";
  {
    ResultsWriter writer(dir, results.machine, results.settings);
    for (Record r : results.records) {
      if (r.strategy == "cpu-coxdeboor" && r.scene == "patch144")
        r.extra_phases["frame"] = PhaseStats{0.002, 0.0025, 0.003};
      writer.append(r);
    }
  }
  const std::string out = tmp_ / "report";
  ASSERT_EQ(run_cli({"report", "--results", dir, "--out", out, "--error-images", "0"}).exit_code,
            0);
  const std::string md = read_text(fs::path(out) / "REPORT.md");
  EXPECT_NE(md.find("| cpu-coxdeboor | patch144 | 4x4 | 2.5 ms | 400 |"), std::string::npos) << md;
}

TEST_F(CliReport, SeveralResultsSetsAreOneReport) {
  const std::string out = tmp_ / "report";
  const CliResult r = run_cli({"report", "--results", results_.string(), "--results",
                               copy_results("second"), "--out", out, "--error-images", "0"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(read_text(fs::path(out) / "REPORT.md").find("| second |"), std::string::npos);
}

// The same measurement in two sets of one machine and commit (a Fig 7 run and an accuracy run
// both hold patch144 at 8x8) is one point of its series, not two at the same x.
TEST_F(CliReport, ChartsKeepOnePointPerMeasurementAcrossSets) {
  const auto series_of = [&](const std::vector<std::string>& sets, const std::string& name) {
    std::vector<std::string> args{"report"};
    for (const std::string& set : sets) args.insert(args.end(), {"--results", set});
    const std::string out = tmp_ / name;
    args.insert(args.end(), {"--out", out, "--error-images", "0", "--python", "/bin/false"});
    EXPECT_EQ(run_cli(args).exit_code, 0);
    std::map<std::string, json> series;
    const json charts = json::parse(read_text(fs::path(out) / "charts.json"));
    for (const json& chart : charts["charts"])
      if (chart["id"] == "fig7_time_vs_points" || chart["id"] == "fig8_many_surfaces")
        series[chart["id"]] = chart["series"];
    return series;
  };
  const auto one = series_of({results_.string()}, "one");
  const auto two = series_of({results_.string(), copy_results("again")}, "two");
  ASSERT_EQ(one.size(), 2u);
  EXPECT_GT(one.at("fig7_time_vs_points").size(), 2u);
  EXPECT_EQ(one, two);
}

// A pair whose strategy chose its own samples has no image layout: it is listed with that reason
// and the next worst pair is drawn instead.
TEST_F(CliReport, ErrorMapsSkipPairsWithoutAnImageLayout) {
  Record own_samples = synthetic("glu-nurbs", 1e6, 50);
  Record grid = synthetic("cpu-coxdeboor", 1e6, 3);
  for (Record* r : {&own_samples, &grid}) r->samples = "16x16";
  const std::string dir = tmp_ / "worst";
  {
    ResultsWriter writer(dir, json{{"cpu_model", "Test CPU"}}, json::object());
    writer.append(own_samples);
    writer.append(grid);
  }
  const std::string out = tmp_ / "report";
  const CliResult r = run_cli({"report", "--results", dir, "--out", out, "--error-images", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string md = read_text(fs::path(out) / "REPORT.md");
  EXPECT_NE(md.find("| glu-nurbs | patch144 | 16x16 | f32 | 50 | not drawn: "), std::string::npos)
      << md;
  EXPECT_NE(md.find("![error-cpu-coxdeboor-patch144.png](error-cpu-coxdeboor-patch144.png)"),
            std::string::npos)
      << md;
  EXPECT_TRUE(fs::exists(fs::path(out) / "error-cpu-coxdeboor-patch144.png"));
}

TEST_F(CliReport, BadInputIsExitTwoWithOneLineAndNoOutput) {
  const std::string out = tmp_ / "report";
  expect_usage_error(run_cli({"report", "--results", tmp_ / "missing", "--out", out}),
                     {"missing", "cannot read results file"});
  const std::string not_results = tmp_ / "not-results";
  fs::create_directories(not_results);
  write_text(fs::path(not_results) / "results.json", R"({"format": "other/1", "records": []})");
  expect_usage_error(run_cli({"report", "--results", not_results, "--out", out}),
                     {"results.json", "format", "other/1"});
  // Parsed strictly, as scenes are: a repeated key is refused, naming where it is.
  write_text(fs::path(not_results) / "results.json",
             R"({"format": "nurbsbench-results/1", "records": [], "records": []})");
  expect_usage_error(run_cli({"report", "--results", not_results, "--out", out}),
                     {"results.json", "records", "duplicate key"});
  expect_usage_error(
      run_cli({"report", "--results", results_.string(), "--out", out, "--error-images", "-1"}),
      {"--error-images", "-1"});
  expect_usage_error(run_cli({"report", "--out", out}), {"--results"});

  struct Case {
    std::string file, text;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {"lod.json", "{not json", {"lod.json", "not valid JSON"}},
      {"lod.json",
       R"({"format": "nurbsbench-lod/2", "rows": []})",
       {"lod.json", "format", "lod/2"}},
      {"lod.json", R"({"format": "nurbsbench-lod/1", "rows": 5})", {"lod.json", "rows", "list"}},
      {"memory.json",
       R"({"format": "nurbsbench-memory/1", "rows": [3]})",
       {"memory.json", "rows[0]", "object"}},
      {"memory.json", R"([1, 2])", {"memory.json", "format", "(missing)"}},
      // Strict fields: a required one missing, or of the wrong type, names file, row and value.
      {"lod.json",
       R"({"format": "nurbsbench-lod/1", "rows": [{"scene": "tan21x23", "samples": "8x8",
           "device": {"name": "x", "kind": "gpu"}, "coarser_by_haar_s": null}]})",
       {"lod.json", "rows[0].coarser_by_haar_s", "null", "number"}},
      {"lod.json",
       R"({"format": "nurbsbench-lod/1", "rows": [{"scene": "tan21x23", "samples": "8x8",
           "device": {"name": "x", "kind": "gpu"}, "coarser_by_haar_s": 1,
           "coarser_by_reevaluation_s": 1, "finer_by_haar_s": 1, "finer_by_reevaluation_s": 1,
           "levels": [{"level": "one"}]}]})",
       {"lod.json", "rows[0].levels[0].level", "\"one\"", "integer"}},
      {"memory.json",
       R"({"format": "nurbsbench-memory/1", "rows": [{"scene": "teapot", "surfaces": -3}]})",
       {"memory.json", "rows[0].surfaces", "-3", "non-negative integer"}},
      {"camera_path.json",
       R"({"format": "nurbsbench-camera-path/1", "rows": [{"scene": "teapot"}]})",
       {"camera_path.json", "rows[0].surfaces", "(missing)", "required"}},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const std::string dir = copy_results(fmt::format("bad{}", k));
    write_text(fs::path(dir) / cases[k].file, cases[k].text);
    SCOPED_TRACE(cases[k].text);
    expect_usage_error(run_cli({"report", "--results", dir, "--out", out}), cases[k].expect);
  }
  EXPECT_FALSE(fs::exists(out)) << "nothing may be written for bad input";
}

// ------------------------------------------------------------------------------ paper vs measured

// patch144 records of `strategy` on `device`: evaluate medians at 16 points and at 4M points.
std::vector<Record> fig7_records(const std::string& strategy, const DeviceInfo& device,
                                 double small_s, double large_s) {
  std::vector<Record> out;
  for (const auto& [samples, points, s] :
       {std::tuple{"4x4", 16, small_s}, std::tuple{"2048x2048", 2048 * 2048, large_s}}) {
    Record r = synthetic(strategy, 1e6, 1);
    r.device = device;
    r.samples = samples;
    r.points = static_cast<std::size_t>(points);
    r.evaluate = {s, s, s};
    out.push_back(r);
  }
  return out;
}

// A row of the claims table: column header -> cell.
using ClaimRow = std::map<std::string, std::string>;

// The claims table of `report`: claim (figure and quote prefix) -> its rows by "measured on".
std::map<std::string, std::map<std::string, ClaimRow>> claims_by_device(const Report& report) {
  const auto s = std::find_if(report.sections.begin(), report.sections.end(),
                              [](const ReportSection& x) { return x.id == "claims"; });
  std::map<std::string, std::map<std::string, ClaimRow>> claims;
  if (s == report.sections.end() || s->tables.empty()) {
    ADD_FAILURE() << "no claims section";
    return claims;
  }
  const auto& header = s->tables.front().header;
  std::map<std::string, std::string> measured_as;
  for (const auto& row : s->tables.front().rows) {
    EXPECT_EQ(row.size(), header.size());
    ClaimRow cells;
    for (std::size_t c = 0; c < header.size() && c < row.size(); ++c) cells[header[c]] = row[c];
    // Two claims share a quote (Fig 8 untrimmed and trimmed): the second by what it measures.
    std::string claim = cells["figure"] + " " + cells["claim (quoted)"].substr(0, 20);
    if (measured_as.contains(claim) && measured_as[claim] != cells["measured as"])
      claim += " [" + cells["measured as"].substr(0, 12) + "]";
    measured_as.emplace(claim, cells["measured as"]);
    EXPECT_TRUE(claims[claim].emplace(cells["measured on"], cells).second)
        << "two rows of " << claim << " on " << cells["measured on"];
  }
  return claims;
}

// The claims table of the report built from `records` (one set, one device per claim): claim
// quote prefix -> row.
std::map<std::string, ClaimRow> claims_of(std::vector<Record> records) {
  ResultSet set;
  set.directory = "results/synthetic";
  set.tag = "synthetic";
  set.results.machine = json{{"cpu_model", "Test CPU"}};
  set.results.records = std::move(records);
  std::map<std::string, ClaimRow> rows;
  for (const auto& [claim, by_device] : claims_by_device(build_report({set}))) {
    EXPECT_EQ(by_device.size(), 1u) << claim;
    rows[claim] = by_device.begin()->second;
  }
  return rows;
}
const std::string kHolds = "holds?", kMeasured = "measured", kWhy = "why (from the measurements)",
                  kCommand = "command that made the data", kOn = "measured on";
const std::string kFig7Large = "Fig 7 The GPU-based evalua";
const std::string kFig7Small = "Fig 7 the GPU evaluation h";

// Fig 14 with glsl-deboor measured in both draw modes (the records' device detail "draw"): two
// series, both in the table, and a note with each mode's draws and median from the records.
TEST(ReportFig14, ShowsBothGlslDeBoorDrawModes) {
  std::vector<Record> records;
  for (const auto& [strategy, draw, draws, median] :
       {std::tuple{"glsl-deboor", "per-span", "506", 0.112},
        std::tuple{"glsl-deboor", "instanced", "2", 0.056},
        std::tuple{"gl-pingpong", "", "", 0.02}}) {
    Record r = synthetic(strategy, 1e6, 1);
    r.scene = "tan256";
    r.device = {"llvmpipe", "cpu", {}};
    if (*draw) r.device.details = {{"draw", draw}, {"draws", draws}};
    r.evaluate = {median, median, median};
    records.push_back(r);
  }
  ResultSet set;
  set.directory = "results/synthetic";
  set.tag = "synthetic";
  set.results.machine = json{{"cpu_model", "Test CPU"}};
  set.results.records = records;
  const Report report = build_report({set});
  const auto s =
      std::find_if(report.sections.begin(), report.sections.end(),
                   [](const ReportSection& x) { return x.id == "fig14_deboor_vs_basis"; });
  ASSERT_NE(s, report.sections.end());
  std::set<std::string> labels;
  for (const json& chart : report.charts["charts"])
    if (chart["id"] == "fig14_deboor_vs_basis")
      for (const json& series : chart["series"]) labels.insert(series["label"].get<std::string>());
  EXPECT_EQ(labels,
            (std::set<std::string>{"gl-pingpong", "glsl-deboor", "glsl-deboor (instanced)"}));
  ASSERT_FALSE(s->tables.empty());
  const auto& header = s->tables.front().header;
  EXPECT_NE(std::find(header.begin(), header.end(), "glsl-deboor (instanced)"), header.end());
  EXPECT_NE(std::find(header.begin(), header.end(), "glsl-deboor"), header.end());
  const std::string md = report_markdown(report);
  EXPECT_NE(md.find("glsl-deboor (instanced)"), std::string::npos);
  EXPECT_NE(md.find("tan256: per span 506 draws, 0.112 s; instanced 2 draws, 0.056 s (ratio 2.00)"),
            std::string::npos)
      << md;
}

TEST(ReportClaims, AGpuFiftyTimesFasterHoldsAndIsSlowerOnTheSmallestGrid) {
  std::vector<Record> records =
      fig7_records("cpu-coxdeboor", {"host CPU, 1 thread", "cpu", {}}, 1e-6, 0.5);
  for (const Record& r : fig7_records("gl-pingpong", {"Test GPU", "gpu", {}}, 1e-3, 0.005))
    records.push_back(r);
  const auto rows = claims_of(records);
  ASSERT_TRUE(rows.contains(kFig7Large));
  const ClaimRow& large = rows.at(kFig7Large);
  EXPECT_EQ(large.at(kHolds), "holds");
  EXPECT_EQ(large.at(kOn), "GPU: Test GPU");
  EXPECT_NE(large.at(kMeasured).find("= 100×"), std::string::npos) << large.at(kMeasured);
  EXPECT_EQ(large.at(kWhy), "");
  EXPECT_NE(large.at(kCommand).find("--out results/synthetic &&"), std::string::npos);
  // The CPU is the side claimed faster here; the verdict is still the GPU's.
  const ClaimRow& small = rows.at(kFig7Small);
  EXPECT_EQ(small.at(kHolds), "holds");
  EXPECT_EQ(small.at(kOn), "GPU: Test GPU");
  EXPECT_NE(small.at(kMeasured).find("= 1e+03×"), std::string::npos) << small.at(kMeasured);
  // Records the results lack: said, with the command that makes them.
  const auto fig15 = rows.find("Fig 15 The figure shows tha");
  ASSERT_NE(fig15, rows.end());
  EXPECT_EQ(fig15->second.at(kHolds), "not measured");
  EXPECT_EQ(fig15->second.at(kOn), "-");
  EXPECT_NE(fig15->second.at(kCommand).find("nurbsbench lod"), std::string::npos);
}

TEST(ReportClaims, ACpuStandInSlowerThanTheCpuDoesNotHoldAndSaysWhyFromTheRecords) {
  std::vector<Record> records =
      fig7_records("cpu-coxdeboor", {"host CPU, 1 thread", "cpu", {}}, 1e-6, 0.1);
  // llvmpipe: a software rasterizer, 3x slower at 4M points, with a 0.1 s cost at 16 points.
  for (const Record& r : fig7_records("gl-pingpong", {"llvmpipe (LLVM 15)", "cpu", {}}, 0.1, 0.3))
    records.push_back(r);
  const auto rows = claims_of(records);
  ASSERT_TRUE(rows.contains(kFig7Large));
  const ClaimRow& row = rows.at(kFig7Large);
  EXPECT_EQ(row.at(kHolds), "does not hold");
  EXPECT_EQ(row.at(kOn), "CPU stand-in (llvmpipe)");
  EXPECT_NE(row.at(kMeasured).find("0.333× (3× the other way)"), std::string::npos)
      << row.at(kMeasured);
  const std::string& why = row.at(kWhy);
  EXPECT_NE(why.find("llvmpipe (LLVM 15)"), std::string::npos) << why;
  EXPECT_NE(why.find("device kind \"cpu\""), std::string::npos) << why;
  EXPECT_NE(why.find("fixed cost per evaluation"), std::string::npos) << why;
  EXPECT_NE(why.find("33%"), std::string::npos) << why;
}

TEST(ReportClaims, CpuSidesOnDifferentThreadCountsAreQualified) {
  std::vector<Record> records =
      fig7_records("cpu-coxdeboor", {"host CPU, 1 thread", "cpu", {}}, 1e-6, 0.2);
  for (const Record& r : fig7_records(
           "cpu-tensor", {"host CPU, 2 threads (OpenMP)", "cpu", {{"threads", "2"}}}, 1e-6, 0.01))
    records.push_back(r);
  const auto rows = claims_of(records);
  const auto macri = rows.find("no figure (Tessellation; Optimizations) To speed up the calc");
  ASSERT_NE(macri, rows.end());
  EXPECT_EQ(macri->second.at(kHolds), "holds");
  EXPECT_EQ(macri->second.at(kOn), "CPU (host)");
  EXPECT_NE(macri->second.at(kWhy).find("different devices"), std::string::npos)
      << macri->second.at(kWhy);
  // 20x on 2 threads against 1: 10x per thread, shown beside the factor.
  EXPECT_NE(macri->second.at(kMeasured).find(
                "= 20× (cpu-tensor on 2 threads, cpu-coxdeboor on 1: 10× per thread)"),
            std::string::npos)
      << macri->second.at(kMeasured);
}

// The paper's own factor decides, in three classes: Fig 7's "about 50" holds at 50x, holds within
// 2x from 25x, and does not hold below.
TEST(ReportClaims, VerdictClassesAreOfThePapersOwnFactor) {
  for (const auto& [cpu_s, verdict] : {std::pair{0.6, "holds"}, std::pair{0.3, "holds within 2×"},
                                       std::pair{0.2, "does not hold"}}) {
    std::vector<Record> records =
        fig7_records("cpu-coxdeboor", {"host CPU, 1 thread", "cpu", {}}, 1e-6, cpu_s);
    for (const Record& r : fig7_records("gl-pingpong", {"Test GPU", "gpu", {}}, 1e-3, 0.01))
      records.push_back(r);
    const ClaimRow row = claims_of(records).at(kFig7Large);
    EXPECT_EQ(row.at(kHolds), verdict) << row.at(kMeasured);
    EXPECT_NE(row.at("holds when").find("≥ 50×"), std::string::npos);
    EXPECT_NE(row.at("clock").find("wall clock"), std::string::npos);
  }
}

// Fig 14 compares two GPU passes by the device's clock: at 256² the host's cost per call would
// decide a wall-clock ratio (2x here), the device's says 20x.
TEST(ReportClaims, Fig14IsReadFromTheDevicesClock) {
  std::vector<Record> records;
  for (const auto& [strategy, wall_s, device_s] :
       {std::tuple{"glsl-deboor", 0.010, 0.001}, std::tuple{"gl-pingpong", 0.020, 0.020}}) {
    Record r = synthetic(strategy, 1e6, 1);
    r.scene = "tan64";
    r.samples = "256x256";
    r.device = {"Test GPU", "gpu", {}};
    r.evaluate = {wall_s, wall_s, wall_s};
    r.device_evaluate_median_s = device_s;
    records.push_back(r);
  }
  const ClaimRow row = claims_of(records).at("Fig 14 The figure shows tha");
  EXPECT_EQ(row.at(kHolds), "holds") << row.at(kMeasured);
  EXPECT_NE(row.at(kMeasured).find("= 20×"), std::string::npos) << row.at(kMeasured);
  EXPECT_NE(row.at("clock").find("device timestamps"), std::string::npos) << row.at("clock");
}

// RPNS's frame is update + evaluate with the points left on the device; the frame phase's
// read-back is the second, labelled line's.
TEST(ReportClaims, RpnsFrameLeavesTheReadBackOut) {
  std::vector<Record> records;
  for (const auto& [strategy, update_s, evaluate_s, read_back_s] :
       {std::tuple{"vk-ksquad", 0.0001, 0.0009, 0.025},
        std::tuple{"cpu-bezier", 0.05, 0.05, 0.001}}) {
    Record r = synthetic(strategy, 1e6, 1);
    r.scene = "many-256";
    r.samples = "64x64";
    const bool gpu = strategy == std::string("vk-ksquad");
    r.device = {gpu ? "Test GPU" : "host CPU", gpu ? "gpu" : "cpu", {}};
    r.upload = {update_s, update_s, update_s};
    r.evaluate = {evaluate_s, evaluate_s, evaluate_s};
    r.read_back = {read_back_s, read_back_s, read_back_s};
    const double frame = update_s + evaluate_s + read_back_s;
    r.extra_phases["frame"] = {frame, frame, frame};
    records.push_back(r);
  }
  const auto rows = claims_of(records);
  const ClaimRow& on_device = rows.at("§1, §6 (the pipelines of Fig 3) Our experimental tes");
  EXPECT_EQ(on_device.at(kHolds), "holds") << on_device.at(kMeasured);  // 0.1 / 0.001 = 100x
  EXPECT_NE(on_device.at(kMeasured).find("= 100×"), std::string::npos) << on_device.at(kMeasured);
  const ClaimRow& end_to_end =
      rows.at("§1, §6, end to end (another question: the points on the host) Our experimental tes");
  EXPECT_EQ(end_to_end.at(kHolds), "does not hold") << end_to_end.at(kMeasured);  // 0.101 / 0.026
}

// ------------------------------------------------------------------------- several machines

// One machine's Fig 7 results set: cpu-coxdeboor on the host and gl-pingpong on `device`, each at
// 16 and 4M points, written where `nurbsbench run` would (MACHINE/fig7-time-vs-points: the
// directory has the same name on every machine) and read back as the report reads it.
struct MachineRun {
  json machine;
  DeviceInfo device;  // gl-pingpong's
  double cpu_small_s, cpu_large_s, gl_small_s, gl_large_s;
};
ResultSet fig7_set(const fs::path& machine_dir, const MachineRun& m) {
  const fs::path dir = machine_dir / "fig7-time-vs-points";
  {
    ResultsWriter writer(dir, m.machine, json::object());
    for (const Record& r : fig7_records("cpu-coxdeboor", {"host CPU, 1 thread", "cpu", {}},
                                        m.cpu_small_s, m.cpu_large_s))
      writer.append(r);
    for (const Record& r : fig7_records("gl-pingpong", m.device, m.gl_small_s, m.gl_large_s))
      writer.append(r);
  }
  return load_result_set(dir);
}
// A real GPU (GL names it with its bus and instruction set) and a 2-core machine whose GL is
// llvmpipe, from the same commit: only the machine tells their sets apart.
const MachineRun kH200{{{"cpu_model", "Intel(R) Xeon(R) Platinum 8480+"},
                        {"logical_cores", 16},
                        {"threads", 16},
                        {"git_commit", "abc123"}},
                       {"NVIDIA H200/PCIe/SSE2", "gpu", {}},
                       1e-6,
                       0.5,
                       1e-4,
                       0.004};
const MachineRun kLlvmpipe{{{"cpu_model", "AMD EPYC 7B13 64-Core Processor"},
                            {"logical_cores", 2},
                            {"threads", 2},
                            {"git_commit", "abc123"}},
                           {"llvmpipe (LLVM 15.0.6, 256 bits)",
                            "cpu",
                            {{"gl_renderer", "llvmpipe (LLVM 15.0.6, 256 bits)"}}},
                           2e-6,
                           0.2,
                           0.01,
                           0.4};

// The factor the claims table prints for slow / fast (report_number, 3 significant digits).
std::string factor(double slow_s, double fast_s) {
  const double r = slow_s / fast_s;
  return r < 1 ? fmt::format("= {:.3g}× ({:.3g}× the other way)", r, 1 / r)
               : fmt::format("= {:.3g}×", r);
}

TEST(ReportMachines, EachClaimHasAVerdictPerDevice) {
  TempDir tmp;
  const std::vector<ResultSet> sets = {fig7_set(tmp.path() / "h200", kH200),
                                       fig7_set(tmp.path() / "cpu", kLlvmpipe)};
  ASSERT_EQ(sets[0].tag, sets[1].tag);
  const Report report = build_report(sets);
  const auto claims = claims_by_device(report);

  // 000 Fig 7 at the largest grid: cpu-coxdeboor / gl-pingpong, at least 10x.
  ASSERT_TRUE(claims.contains(kFig7Large));
  const auto& large = claims.at(kFig7Large);
  ASSERT_EQ(large.size(), 2u);
  ASSERT_TRUE(large.contains("GPU: NVIDIA H200"));
  const ClaimRow& gpu = large.at("GPU: NVIDIA H200");
  EXPECT_EQ(gpu.at(kHolds), kH200.cpu_large_s / kH200.gl_large_s >= 10 ? "holds" : "does not hold");
  EXPECT_EQ(gpu.at(kHolds), "holds");
  EXPECT_NE(gpu.at(kMeasured).find(factor(kH200.cpu_large_s, kH200.gl_large_s)), std::string::npos)
      << gpu.at(kMeasured);
  EXPECT_EQ(gpu.at(kMeasured).find("geometric mean"), std::string::npos) << gpu.at(kMeasured);
  EXPECT_EQ(gpu.at(kWhy), "");
  EXPECT_NE(gpu.at(kCommand).find("--out " + sets[0].directory.string() + " &&"), std::string::npos)
      << gpu.at(kCommand);
  ASSERT_TRUE(large.contains("CPU stand-in (llvmpipe)"));
  const ClaimRow& cpu = large.at("CPU stand-in (llvmpipe)");
  EXPECT_EQ(cpu.at(kHolds), "does not hold");
  EXPECT_NE(cpu.at(kMeasured).find(factor(kLlvmpipe.cpu_large_s, kLlvmpipe.gl_large_s)),
            std::string::npos)
      << cpu.at(kMeasured);
  EXPECT_NE(cpu.at(kWhy).find("ran on llvmpipe (LLVM 15.0.6, 256 bits)"), std::string::npos)
      << cpu.at(kWhy);
  EXPECT_NE(cpu.at(kCommand).find("--out " + sets[1].directory.string() + " &&"), std::string::npos)
      << cpu.at(kCommand);

  // At the smallest grid the CPU is the side claimed faster; each verdict is still its GPU's.
  ASSERT_TRUE(claims.contains(kFig7Small));
  const auto& small = claims.at(kFig7Small);
  ASSERT_EQ(small.size(), 2u);
  for (const auto& [on, run] :
       {std::pair{"GPU: NVIDIA H200", kH200}, std::pair{"CPU stand-in (llvmpipe)", kLlvmpipe}}) {
    ASSERT_TRUE(small.contains(on)) << on;
    EXPECT_EQ(small.at(on).at(kHolds), "holds") << on;
    EXPECT_NE(small.at(on).at(kMeasured).find(factor(run.gl_small_s, run.cpu_small_s)),
              std::string::npos)
        << small.at(on).at(kMeasured);
  }
  // A claim neither machine measured keeps its one row.
  ASSERT_TRUE(claims.contains("Fig 15 The figure shows tha"));
  EXPECT_EQ(claims.at("Fig 15 The figure shows tha").size(), 1u);
  EXPECT_EQ(claims.at("Fig 15 The figure shows tha").begin()->second.at(kHolds), "not measured");
}

// Series of a chart: label -> y values in x order.
std::map<std::string, std::vector<double>> chart_series(const Report& report,
                                                        const std::string& id) {
  std::map<std::string, std::vector<double>> out;
  for (const json& chart : report.charts["charts"])
    if (chart["id"] == id)
      for (const json& s : chart["series"])
        out[s["label"].get<std::string>()] = s["y"].get<std::vector<double>>();
  return out;
}

TEST(ReportMachines, ChartSeriesNameTheMachineWhereThereAreSeveral) {
  TempDir tmp;
  const ResultSet h200 = fig7_set(tmp.path() / "h200", kH200),
                  cpu = fig7_set(tmp.path() / "cpu", kLlvmpipe);
  const auto two = chart_series(build_report({h200, cpu}), "fig7_time_vs_points");
  const std::map<std::string, std::vector<double>> expected = {
      {"cpu-coxdeboor [NVIDIA H200]", {kH200.cpu_small_s, kH200.cpu_large_s}},
      {"gl-pingpong [NVIDIA H200]", {kH200.gl_small_s, kH200.gl_large_s}},
      {"cpu-coxdeboor [AMD EPYC 7B13 2t]", {kLlvmpipe.cpu_small_s, kLlvmpipe.cpu_large_s}},
      {"gl-pingpong [AMD EPYC 7B13 2t]", {kLlvmpipe.gl_small_s, kLlvmpipe.gl_large_s}}};
  EXPECT_EQ(two, expected);
  // Tables name each set by its machine too: both sets are "fig7-time-vs-points".
  const std::string md = report_markdown(build_report({h200, cpu}));
  EXPECT_NE(md.find("| fig7-time-vs-points [NVIDIA H200] |"), std::string::npos) << md;
  EXPECT_NE(md.find("| fig7-time-vs-points [AMD EPYC 7B13 2t] |"), std::string::npos) << md;

  // Another set of the H200 machine, from another commit, its GPU named as Vulkan names it: the
  // same machine, so no suffix.
  MachineRun again = kH200;
  again.machine["git_commit"] = "def456";
  again.device.name = "NVIDIA H200";
  const ResultSet h200_again = fig7_set(tmp.path() / "h200-again", again);
  std::set<std::string> labels;
  for (const auto& [label, ys] :
       chart_series(build_report({h200, h200_again}), "fig7_time_vs_points"))
    labels.insert(label);
  EXPECT_EQ(labels, (std::set<std::string>{"cpu-coxdeboor", "gl-pingpong"}));

  // Two machines with the same GPU and different CPUs: the GPU's name alone does not tell them
  // apart, so the labels add the CPU.
  MachineRun other_host = kH200;
  other_host.machine["cpu_model"] = "AMD EPYC 9654 96-Core Processor";
  other_host.machine["logical_cores"] = 192;
  other_host.gl_large_s = 0.003;
  const auto same_gpu = chart_series(
      build_report({h200, fig7_set(tmp.path() / "other-host", other_host)}), "fig7_time_vs_points");
  ASSERT_EQ(same_gpu.size(), 4u);
  ASSERT_TRUE(same_gpu.contains("gl-pingpong [NVIDIA H200, AMD EPYC 9654 192t]"));
  EXPECT_EQ(same_gpu.at("gl-pingpong [NVIDIA H200, AMD EPYC 9654 192t]"),
            (std::vector<double>{other_host.gl_small_s, other_host.gl_large_s}));
  ASSERT_TRUE(same_gpu.contains("gl-pingpong [NVIDIA H200, Intel Xeon Platinum 8480+ 16t]"));
}

// ---------------------------------------------------------------------------------- recommend

class CliRecommend : public ::testing::Test {
 protected:
  std::string write_results(const std::vector<Record>& records) {
    const std::string dir = tmp_ / fmt::format("results{}", ++count_);
    ResultsWriter writer(dir, json{{"cpu_model", "Test CPU"}}, json::object());
    for (const Record& r : records) writer.append(r);
    return dir;
  }
  std::vector<Record> standard() {
    Record limit = synthetic("limit-store-bandwidth", 1e12, 0);
    limit.role = "limit";
    limit.accuracy.reset();
    return {synthetic("fast-but-rough", 4e9, 10), synthetic("middle", 2e9, 2),
            synthetic("slow-and-exact", 1e9, 0.5), synthetic("broken", 9e9, 0, Status::failed),
            limit};
  }
  TempDir tmp_;
  int count_ = 0;
};

TEST_F(CliRecommend, RanksByThroughputWithinTheToleranceAndSaysWhyOthersAreOut) {
  const CliResult r = run_cli({"recommend", "--results", write_results(standard()), "--scene",
                               "patch144", "--tolerance", "4ulp", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["ranked"].size(), 2u) << r.out;
  EXPECT_EQ(j["ranked"][0]["strategy"], "middle");
  EXPECT_EQ(j["ranked"][1]["strategy"], "slow-and-exact");
  EXPECT_NEAR(j["ranked"][0]["points_per_s"].get<double>(), 2e9, 1);
  ASSERT_EQ(j["excluded"].size(), 2u);
  for (const json& e : j["excluded"]) {
    if (e["strategy"] == "fast-but-rough")
      EXPECT_NE(e["excluded"].get<std::string>().find("max_ulp 10 exceeds the tolerance 4 ulp"),
                std::string::npos)
          << e;
    else
      EXPECT_EQ(e["excluded"], "failed on patch144 256x256: device lost");
  }
  EXPECT_EQ(r.out.find("limit-store-bandwidth"), std::string::npos) << "a limit is no candidate";

  const CliResult text =
      run_cli({"recommend", "--results", write_results(standard()), "--tolerance", "4ulp"});
  ASSERT_EQ(text.exit_code, 0);
  EXPECT_LT(text.out.find("1    middle"), text.out.find("2    slow-and-exact")) << text.out;
  EXPECT_NE(text.out.find("excluded:\n"), std::string::npos);
}

TEST_F(CliRecommend, ToleranceInModelUnitsComparesMaxAbs) {
  const CliResult r = run_cli(
      {"recommend", "--results", write_results(standard()), "--tolerance", "5e-7", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["ranked"].size(), 2u);  // max_abs 2e-7 and 5e-8 are in; 1e-6 is out
  EXPECT_EQ(j["tolerance"]["unit"], "model");
}

TEST_F(CliRecommend, NothingWithinToleranceIsExitOne) {
  const CliResult r =
      run_cli({"recommend", "--results", write_results(standard()), "--tolerance", "0.1ulp"});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.out.find("no strategy meets the tolerance"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("slow-and-exact f32: max_ulp 0.5 exceeds"), std::string::npos) << r.out;
}

TEST_F(CliRecommend, OnlyOneStrategyAvailable) {
  std::vector<Record> records = {synthetic("only-one", 1e8, 1),
                                 synthetic("missing", 0, 0, Status::unavailable)};
  const CliResult r =
      run_cli({"recommend", "--results", write_results(records), "--tolerance", "8ulp", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["ranked"].size(), 1u);
  EXPECT_EQ(j["ranked"][0]["strategy"], "only-one");
  EXPECT_EQ(j["excluded"][0]["excluded"], "unavailable on patch144 256x256: device lost");
}

// A trimmed scene none of whose samples is inside a face: 0 error over nothing is no score.
TEST_F(CliRecommend, NoSampleInsideATrimmedFaceIsExcludedNotPerfect) {
  std::vector<Record> records = standard();
  TrimAccuracy nothing_inside;
  nothing_inside.inside = 0;
  records[0].accuracy->max_ulp = records[0].accuracy->max_abs = 0;
  records[0].accuracy->trim = nothing_inside;  // fast-but-rough
  const CliResult r =
      run_cli({"recommend", "--results", write_results(records), "--tolerance", "4ulp", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["ranked"].size(), 2u) << r.out;
  EXPECT_EQ(j["ranked"][0]["strategy"], "middle");
  bool said_why = false;
  for (const json& e : j["excluded"])
    if (e["strategy"] == "fast-but-rough")
      said_why = e["excluded"] ==
                 "no sample inside a trimmed face on patch144 256x256: its errors are over nothing";
  EXPECT_TRUE(said_why) << r.out;
}

TEST_F(CliRecommend, DeformingRanksByFrameTime) {
  std::vector<Record> records = standard();
  records[2].extra_phases["frame"] = PhaseStats{0.001, 0.001, 0.001};  // slow-and-exact
  const CliResult r = run_cli({"recommend", "--results", write_results(records), "--tolerance",
                               "4ulp", "--deforming", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["ranked"].size(), 1u);
  EXPECT_EQ(j["ranked"][0]["strategy"], "slow-and-exact");
  EXPECT_NEAR(j["ranked"][0]["points_per_s"].get<double>(), 65536e3, 1);
}

TEST_F(CliRecommend, QuickMeasurementOfAParametricWorkload) {
  const CliResult r = run_cli({"recommend", "--degree", "2", "--control-net", "6x5", "--samples",
                               "8x8", "--repetitions", "1", "--tolerance", "1e6ulp", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_FALSE(j["ranked"].empty());
  const std::vector<std::string> known = strategy_names();
  for (const json& c : j["ranked"])
    EXPECT_NE(std::find(known.begin(), known.end(), c["strategy"].get<std::string>()), known.end());
  EXPECT_NE(j["scope"].get<std::string>().find("workload-d2-6x5-s1"), std::string::npos);
}

TEST_F(CliRecommend, BadInputIsExitTwo) {
  const std::string results = write_results(standard());
  expect_usage_error(run_cli({"recommend", "--results", results, "--tolerance", "abc"}),
                     {"--tolerance", "abc"});
  expect_usage_error(run_cli({"recommend", "--results", results, "--tolerance", "-3ulp"}),
                     {"--tolerance", "-3ulp"});
  expect_usage_error(
      run_cli({"recommend", "--results", results, "--scene", "teapot", "--tolerance", "8ulp"}),
      {"no measurement matches", "teapot", "patch144"});
  expect_usage_error(run_cli({"recommend", "--results", results, "--degree", "3", "--surfaces", "4",
                              "--tolerance", "8ulp"}),
                     {"--scene"});
  expect_usage_error(run_cli({"recommend", "--degree", "0", "--tolerance", "8ulp"}), {"--degree"});
  expect_usage_error(run_cli({"recommend", "--control-net", "2x2", "--tolerance", "8ulp"}),
                     {"--control-net"});
  expect_usage_error(run_cli({"recommend", "--results", results}), {"--tolerance"});
}

// ------------------------------------------------------------------------------- gbench-json

TEST_F(CliRecommend, GbenchJsonHasGoogleBenchmarksSchema) {
  const std::string out = tmp_ / "gb.json";
  const CliResult r =
      run_cli({"gbench-json", "--results", write_results(standard()), "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(read_text(out));
  ASSERT_TRUE(j.contains("context") && j["context"].contains("date"));
  // 3 measured strategies x (evaluate, end_to_end) + the limit row; the failed one is left out.
  ASSERT_EQ(j["benchmarks"].size(), 7u);
  for (const json& b : j["benchmarks"]) {
    for (const char* key : {"name", "run_type", "real_time", "cpu_time", "time_unit", "iterations"})
      EXPECT_TRUE(b.contains(key)) << key << " in " << b;
    EXPECT_EQ(b["run_type"], "iteration");
    EXPECT_EQ(b["time_unit"], "us");
    EXPECT_EQ(b["name"].get<std::string>().find("broken"), std::string::npos);
  }
  EXPECT_EQ(j["benchmarks"][2]["name"], "middle/patch144/256x256/f32");
  EXPECT_NEAR(j["benchmarks"][2]["real_time"].get<double>(), 65536 / 2e9 * 1e6, 1e-9);
  expect_usage_error(run_cli({"gbench-json", "--results", tmp_ / "none"}), {"none"});
}

// ------------------------------------------------------------------------------- error images

class CliErrorImage : public ::testing::Test {
 protected:
  TempDir tmp_;
};

TEST_F(CliErrorImage, ExrHoldsTheErrorOfEverySampleAgainstTheReference) {
  const std::string exr = tmp_ / "e.exr", csv = tmp_ / "p.csv";
  // cpu-coxdeboor in f32: errors of a few ulps, and in every build (the sanitizer one is CPU-only).
  const CliResult r = run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                               "--samples", "16x12", "--error-image", exr, "--out", csv});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto in = OIIO::ImageInput::open(exr);
  ASSERT_TRUE(in) << OIIO::geterror();
  const OIIO::ImageSpec spec = in->spec();
  ASSERT_EQ(spec.width, 16);
  ASSERT_EQ(spec.height, 12);
  ASSERT_EQ(spec.nchannels, 1);
  std::vector<float> pixels(16 * 12);
  ASSERT_TRUE(in->read_image(0, 0, 0, 1, OIIO::TypeDesc::FLOAT, pixels.data()));
  in->close();

  // Independently: the CSV's positions against the reference at the CSV's (u, v).
  const Scene scene = *make_builtin_scene("patch144");
  const std::vector<std::string> lines = split_lines(read_text(csv));
  ASSERT_EQ(lines.size(), 1u + 16 * 12);
  for (int k : {0, 5, 17, 100, 191}) {  // CSV order: u-index a, then v-index b
    const std::vector<std::string> f = split_csv(lines[1 + k]);
    SurfaceSamples one;
    one.tensor = false;
    one.u = {std::stod(f[1])};
    one.v = {std::stod(f[2])};
    const Point3 ref = evaluate_reference(scene, {one}, false)[0].positions[0];
    const double error =
        // f32 coordinates are printed in shortest float form: read them back as floats.
        std::hypot(double{std::stof(f[3])} - ref[0], double{std::stof(f[4])} - ref[1],
                   double{std::stof(f[5])} - ref[2]);
    const int a = k / 12, b = k % 12;
    EXPECT_NEAR(pixels[b * 16 + a], error, 1e-6 * error + 1e-15) << "sample " << k;
  }
  EXPECT_GT(*std::max_element(pixels.begin(), pixels.end()), 0.0f);
}

TEST_F(CliErrorImage, PngHasTheDocumentedSizeAndOneFilePerSurface) {
  const std::string png = tmp_ / "m.png";
  const CliResult r =
      run_cli({"eval", "--scene", "many-4", "--strategy", "cpu-coxdeboor", "--samples", "16x12",
               "--error-image", png, "--out", tmp_ / "p.csv"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(png));
  for (int i = 0; i < 4; ++i) {
    const std::string path = tmp_ / fmt::format("m-{}.png", i);
    auto in = OIIO::ImageInput::open(path);
    ASSERT_TRUE(in) << path;
    const auto [w, h] = error_png_size(16, 12);
    EXPECT_EQ(in->spec().width, w);
    EXPECT_EQ(in->spec().height, h);
    EXPECT_EQ(w, 16 * 16 + kLegendWidth);
    EXPECT_EQ(h, 256);
  }
}

TEST_F(CliErrorImage, ExplicitListOrUnknownFormatIsExitTwoAndWritesNothing) {
  const std::string uv = tmp_ / "uv.csv", out = tmp_ / "p.csv";
  write_text(uv, "0,0.5,0.5\n0,0.25,0.75\n");
  expect_usage_error(run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--uv",
                              uv, "--error-image", tmp_ / "e.png", "--out", out}),
                     {"--error-image", "explicit", "--uv"});
  expect_usage_error(run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                              "--error-image", tmp_ / "e.jpg", "--out", out}),
                     {"--error-image", ".jpg", ".exr", ".png"});
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(tmp_ / "e.png"));
}

}  // namespace
}  // namespace nurbs::test
