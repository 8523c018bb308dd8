// The `nurbsbench` verbs as a user drives them: list, eval, run, check; their outputs' shapes and
// exit codes (0 success, 1 a gate failed, 2 bad usage or input, with one stderr line).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "reference/sampling.h"
#include "run_cli.h"
#include "scenes/builtin_scenes.h"
#include "scenes/scene_json.h"
#include "strategies/registry.h"
#include "tests/harness/plates.h"
#include "tests/scenes/trimmed_plate_closed_form.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const char* const kResultsCsvHeader =
    "scene,strategy,device,precision,sampling,samples,points,setup_s,upload_median_s,"
    "evaluate_min_s,evaluate_median_s,evaluate_max_s,readback_median_s,end_to_end_median_s,"
    "throughput_pts_per_s,max_abs,rms_abs,max_rel,max_ulp,status,reason,trimming,trim_band,"
    "trim_inside_samples,trim_boundary_samples,trim_misclassified,trim_misclassified_rate";

Scene builtin(std::string_view name) {
  return *make_builtin_scene(name);
}

double parse_exact(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  EXPECT_EQ(end, text.c_str() + text.size()) << "not a number: '" << text << "'";
  return value;
}

// Rows of an eval CSV, split into fields; the header is checked and dropped.
std::vector<std::vector<std::string>> eval_rows(const std::string& csv, const std::string& header) {
  const std::vector<std::string> lines = split_lines(csv);
  EXPECT_FALSE(lines.empty());
  if (lines.empty()) return {};
  EXPECT_EQ(lines.front(), header);
  std::vector<std::vector<std::string>> rows;
  for (std::size_t k = 1; k < lines.size(); ++k) rows.push_back(split_csv(lines[k]));
  return rows;
}

void expect_usage_error(const CliResult& r, const std::vector<std::string>& substrings) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(is_one_error_line(r.err)) << "stderr:\n" << r.err;
  for (const std::string& s : substrings)
    EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
}

// ---------------------------------------------------------------------------------------- list

TEST(CliList, TextNamesStrategiesAndScenes) {
  const CliResult r = run_cli({"list"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("strategies:"), std::string::npos);
  EXPECT_NE(r.out.find("scenes:"), std::string::npos);
  for (const std::string& name : strategy_names())
    EXPECT_NE(r.out.find(name), std::string::npos) << name;
  for (const BuiltinSceneInfo& s : builtin_scenes())
    EXPECT_NE(r.out.find(s.name), std::string::npos) << s.name;
  EXPECT_NE(r.out.find("limits:\n  limit-store-bandwidth"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\n  limit-device-copy"), std::string::npos) << r.out;
  for (const char* link :
       {"limit-link-vulkan", "limit-link-opencl", "limit-link-gl", "limit-gl-fragment-pass"})
    EXPECT_NE(r.out.find(std::string("\n  ") + link), std::string::npos) << link << r.out;
}

TEST(CliList, JsonDescribesEveryStrategyAndScene) {
  const CliResult r = run_cli({"list", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);  // throws (fails the test) when not valid JSON
  ASSERT_TRUE(doc.contains("strategies") && doc["strategies"].is_array());
  ASSERT_TRUE(doc.contains("scenes") && doc["scenes"].is_array());
  ASSERT_EQ(doc["limits"].size(), 6u);
  EXPECT_EQ(doc["limits"][0]["name"], "limit-store-bandwidth");
  EXPECT_EQ(doc["limits"][1]["name"], "limit-device-copy");
  EXPECT_EQ(doc["limits"][2]["name"], "limit-link-vulkan");
  EXPECT_EQ(doc["limits"][3]["name"], "limit-link-opencl");
  EXPECT_EQ(doc["limits"][4]["name"], "limit-link-gl");
  EXPECT_EQ(doc["limits"][5]["name"], "limit-gl-fragment-pass");

  std::set<std::string> strategies;
  for (const json& s : doc["strategies"]) {
    ASSERT_TRUE(s["name"].is_string()) << s.dump();
    SCOPED_TRACE(s["name"].get<std::string>());
    strategies.insert(s["name"].get<std::string>());
    EXPECT_TRUE(s["available"].is_boolean());
    EXPECT_TRUE(s["reason"].is_string());
    EXPECT_TRUE(s["source"].is_string());
    EXPECT_FALSE(s["source"].get<std::string>().empty());
    // An unavailable strategy says why.
    if (!s["available"].get<bool>()) {
      EXPECT_FALSE(s["reason"].get<std::string>().empty());
    }
    const json& c = s["capabilities"];
    ASSERT_TRUE(c.is_object());
    EXPECT_TRUE(c["max_degree"].is_number_integer());
    EXPECT_TRUE(c["rational"].is_boolean());
    EXPECT_TRUE(c["normals"].is_boolean());
    EXPECT_TRUE(c["precisions"].is_array());
    EXPECT_TRUE(c["sampling"].is_array());
  }
  const std::vector<std::string> names = strategy_names();
  EXPECT_EQ(strategies, std::set<std::string>(names.begin(), names.end()));
  EXPECT_TRUE(strategies.count("cpu-coxdeboor"));

  std::set<std::string> scenes;
  for (const json& s : doc["scenes"]) {
    ASSERT_TRUE(s["name"].is_string()) << s.dump();
    EXPECT_TRUE(s["description"].is_string());
    scenes.insert(s["name"].get<std::string>());
  }
  for (const BuiltinSceneInfo& s : builtin_scenes()) EXPECT_TRUE(scenes.count(s.name)) << s.name;
}

// Per GPU API: a device the strategies use, or why there is none; the driver files read.
TEST(CliList, EachGpuApiNamesItsDeviceOrWhyNone) {
  const CliResult text = run_cli({"list"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  const std::size_t devices = text.out.find("devices (per GPU API; a software device is a CPU):\n");
  ASSERT_NE(devices, std::string::npos) << text.out;
  const CliResult r = run_cli({"list", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);
  ASSERT_TRUE(doc["devices"].is_array());
  std::vector<std::string> apis;
  for (const json& api : doc["devices"]) {
    const std::string name = api["api"].get<std::string>();
    SCOPED_TRACE(name);
    apis.push_back(name);
    EXPECT_NE(text.out.find("\n  " + name + ":\n", devices), std::string::npos) << text.out;
    const std::string unavailable = api["unavailable"].get<std::string>();
    int chosen = 0;
    for (const json& d : api["devices"]) {
      EXPECT_TRUE(d["kind"] == "cpu" || d["kind"] == "gpu") << d.dump();
      chosen += d["details"].value("chosen", "") == "yes";
    }
    // Exactly one device is the default pick, or none is there and the reason says why.
    if (unavailable.empty()) {
      EXPECT_EQ(chosen, 1) << api.dump();
    } else {
      EXPECT_TRUE(api["devices"].empty()) << api.dump();
      EXPECT_NE(text.out.find("    none: " + unavailable), std::string::npos) << text.out;
    }
    for (const json& f : api["driver_files"]) {
      EXPECT_TRUE(f["path"].is_string() && f["library"].is_string() && f["from"].is_string());
      EXPECT_NE(text.out.find("    driver file " + f["path"].get<std::string>()),
                std::string::npos);
    }
  }
  EXPECT_EQ(apis, (std::vector<std::string>{"Vulkan", "OpenGL (EGL)", "OpenCL"}));
}

TEST(CliList, DriverDirThatIsNoFolderIsRefused) {
  expect_usage_error(run_cli({"list", "--driver-dir", "/nonexistent-nurbsbench-driver"}),
                     {"--driver-dir '/nonexistent-nurbsbench-driver': not a folder"});
  TempDir empty;
  expect_usage_error(
      run_cli({"--driver-dir", empty.path().string(), "list"}),
      {"--driver-dir '" + empty.path().string() + "': holds no Vulkan ICD manifest"});
}

// A Vulkan driver the loader cannot see (VK_DRIVER_FILES names nothing) is found through
// --driver-dir: the machine's own manifests, copied into a folder laid out as a driver's.
TEST(CliList, DriverDirBringsADriverTheLoaderDoesNotSee) {
  std::vector<fs::path> manifests;
  for (const char* dir : {"/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"}) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().extension() == ".json") manifests.push_back(e.path());
  }
  const json before = json::parse(run_cli({"list", "--json"}).out);
  if (manifests.empty() || !before["devices"][0]["unavailable"].get<std::string>().empty())
    GTEST_SKIP() << "no Vulkan device on this machine to hide and find again";
  TempDir driver;
  fs::create_directories(driver.path() / "share/vulkan/icd.d");
  for (const fs::path& m : manifests)
    fs::copy_file(m, driver.path() / "share/vulkan/icd.d" / m.filename());
  setenv("VK_DRIVER_FILES", "/nonexistent-nurbsbench.json", 1);
  const CliResult hidden = run_cli({"list", "--json"});
  const CliResult found = run_cli({"list", "--json", "--driver-dir", driver.path().string()});
  unsetenv("VK_DRIVER_FILES");
  ASSERT_EQ(hidden.exit_code, 0) << hidden.err;
  ASSERT_EQ(found.exit_code, 0) << found.err;
  EXPECT_FALSE(json::parse(hidden.out)["devices"][0]["unavailable"].get<std::string>().empty());
  const json vulkan = json::parse(found.out)["devices"][0];
  EXPECT_EQ(vulkan["unavailable"], "") << vulkan.dump();
  EXPECT_EQ(vulkan["devices"].size(), before["devices"][0]["devices"].size());
  bool served = false;
  for (const json& f : vulkan["driver_files"])
    served |= f["path"].get<std::string>().starts_with(driver.path().string()) &&
              !f["loaded"].get<std::string>().empty();
  EXPECT_TRUE(served) << vulkan.dump();
}

// ---------------------------------------------------------------------------------------- help

TEST(CliHelp, EveryVerbHasHelpAndExitsZero) {
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"--help"},
                                             {"list", "--help"},
                                             {"scene", "--help"},
                                             {"eval", "--help"},
                                             {"run", "--help"},
                                             {"lod", "--help"},
                                             {"camera-path", "--help"},
                                             {"check", "--help"},
                                             {"memory", "--help"}}) {
    SCOPED_TRACE(args.front());
    const CliResult r = run_cli(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << r.out;
  }
}

TEST(CliHelp, BadUsageIsExitTwoWithOneLine) {
  expect_usage_error(run_cli({}), {"subcommand"});
  expect_usage_error(run_cli({"eval", "--strategy", "cpu-coxdeboor"}), {"--scene"});
  expect_usage_error(
      run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--bogus"}),
      {"--bogus"});
  expect_usage_error(run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                              "--samples", "4x4", "--span-samples", "2"}),
                     {"--samples", "--span-samples"});
}

// ---------------------------------------------------------------------------------------- eval

TEST(CliEval, GridCsvHasOneRowPerSampleWithExactParameters) {
  TempDir tmp;
  const std::string out = tmp / "points.csv";
  const CliResult r = run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                               "--samples", "7x5", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  const auto rows = eval_rows(read_text(out), "surface,u,v,x,y,z");
  ASSERT_EQ(rows.size(), 35u);

  const Scene scene = builtin("patch144");
  const Surface& s = scene.surfaces[0];
  const std::vector<double> u = grid_parameters(s.u_min(), s.u_max(), 7);
  const std::vector<double> v = grid_parameters(s.v_min(), s.v_max(), 5);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    SCOPED_TRACE(k);
    ASSERT_EQ(rows[k].size(), 6u);
    EXPECT_EQ(rows[k][0], "0");
    // 17 significant digits: the printed parameter reads back as the very double evaluated.
    EXPECT_EQ(parse_exact(rows[k][1]), u[k / 5]) << rows[k][1];
    EXPECT_EQ(parse_exact(rows[k][2]), v[k % 5]) << rows[k][2];
    for (int c = 3; c < 6; ++c) EXPECT_TRUE(std::isfinite(parse_exact(rows[k][c])));
  }
  EXPECT_EQ(rows[1][1], "0");
  EXPECT_EQ(rows[5][1], fmt::format("{:.17g}", u[1]));  // 1/6 needs all 17 digits
  // Clamped knots: the corners of the surface are the corner control points.
  const Point3& p00 = s.point(0, 0);
  const Point3& p_end = s.point(11, 11);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(parse_exact(rows.front()[3 + c]), p00[c], 1e-5);
    EXPECT_NEAR(parse_exact(rows.back()[3 + c]), p_end[c], 1e-5);
  }
}

TEST(CliEval, SpanSamplesCoverEveryNonEmptySpan) {
  // patch144: 12 control points, degree 3, all interior knots distinct -> 9 spans per
  // direction; T = 2 gives 3 samples per span, shared ends repeated: (9 * 3)^2 rows.
  const CliResult r = run_cli(
      {"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--span-samples", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = eval_rows(r.out, "surface,u,v,x,y,z");
  ASSERT_EQ(rows.size(), 27u * 27u);
  // The first span of u is [0, 0.1]: 0, 0.05, 0.1, then the next span starts at 0.1 again.
  EXPECT_EQ(parse_exact(rows[0 * 27][1]), 0.0);
  EXPECT_EQ(parse_exact(rows[1 * 27][1]), 0.05);
  EXPECT_EQ(parse_exact(rows[2 * 27][1]), 0.1);
  EXPECT_EQ(parse_exact(rows[3 * 27][1]), 0.1);
  EXPECT_EQ(parse_exact(rows.back()[1]), 1.0);
  EXPECT_EQ(parse_exact(rows.back()[2]), 1.0);
}

TEST(CliEval, NormalsAddThreeUnitColumns) {
  const CliResult r = run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                               "--samples", "4x3", "--normals"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = eval_rows(r.out, "surface,u,v,x,y,z,nx,ny,nz");
  ASSERT_EQ(rows.size(), 12u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 9u);
    const double nx = parse_exact(row[6]), ny = parse_exact(row[7]), nz = parse_exact(row[8]);
    EXPECT_NEAR(std::sqrt(nx * nx + ny * ny + nz * nz), 1.0, 1e-5);
  }
}

TEST(CliEval, PrecisionF64PrintsDoubles) {
  const std::vector<std::string> args = {"eval",          "--scene",   "patch144", "--strategy",
                                         "cpu-coxdeboor", "--samples", "3x3"};
  std::vector<std::string> f64 = args;
  f64.insert(f64.end(), {"--precision", "f64"});
  const CliResult r32 = run_cli(args), r64 = run_cli(f64);
  ASSERT_EQ(r32.exit_code, 0) << r32.err;
  ASSERT_EQ(r64.exit_code, 0) << r64.err;
  const auto rows32 = eval_rows(r32.out, "surface,u,v,x,y,z");
  const auto rows64 = eval_rows(r64.out, "surface,u,v,x,y,z");
  ASSERT_EQ(rows32.size(), 9u);
  ASSERT_EQ(rows64.size(), 9u);
  const Point3 p00 = builtin("patch144").surfaces[0].point(0, 0);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(parse_exact(rows64[0][3 + c]), p00[c], 1e-12);
  // The f32 values print in shortest float form (they read back as the same float), the f64
  // values as doubles.
  bool some_differ = false;
  for (std::size_t k = 0; k < rows32.size(); ++k)
    for (int c = 3; c < 6; ++c) {
      const double x32 = parse_exact(rows32[k][c]), x64 = parse_exact(rows64[k][c]);
      EXPECT_EQ(fmt::format("{}", std::strtof(rows32[k][c].c_str(), nullptr)), rows32[k][c]);
      EXPECT_NEAR(x32, x64, 1e-4);
      some_differ |= x32 != x64;
    }
  EXPECT_TRUE(some_differ);
  expect_usage_error(
      run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--precision", "f16"}),
      {"--precision", "f16", "f32 or f64"});
}

TEST(CliEval, UnknownStrategyListsTheValidOnes) {
  const CliResult r = run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-nope"});
  expect_usage_error(r, {"cpu-nope", "unknown strategy"});
  for (const std::string& name : strategy_names())
    EXPECT_NE(r.err.find(name), std::string::npos) << name;
}

TEST(CliEval, UnknownSceneListsTheValidOnes) {
  for (const std::string bad : {"patch145", "many-0", "many-4097", "many-x"}) {
    const CliResult r = run_cli({"eval", "--scene", bad, "--strategy", "cpu-coxdeboor"});
    expect_usage_error(r, {"'" + bad + "'", "neither a file nor a built-in scene", "many-N"});
    for (const BuiltinSceneInfo& s : builtin_scenes())
      EXPECT_NE(r.err.find(s.name), std::string::npos) << s.name;
  }
}

TEST(CliEval, BadGridSizesAreRefused) {
  TempDir tmp;
  const std::string out = tmp / "out.csv";
  for (const std::string grid :
       {"0x5", "5x0", "1x1", "-3x3", "70000x2", "abc", "8x", "x8", "8x8x8", "1e3x4", "8.5x8", ""}) {
    SCOPED_TRACE(grid);
    expect_usage_error(run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                                "--samples", grid, "--out", out}),
                       {"--samples", "'" + grid + "'"});
    EXPECT_FALSE(fs::exists(out));
  }
  // Each side within bounds, the product not: refused from the sizes, before any allocation.
  const CliResult r = run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                               "--samples", "65536x65536", "--out", out},
                              {kRejectionMemoryLimit});
  expect_usage_error(r, {"4294967296 samples", "limit"});
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliEval, BadSpanSamplesAreRefused) {
  TempDir tmp;
  const std::string out = tmp / "out.csv";
  for (const std::string steps : {"0", "-1", "99999", "abc", "2.5", ""}) {
    SCOPED_TRACE(steps);
    expect_usage_error(run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                                "--span-samples", steps, "--out", out}),
                       {"--span-samples"});
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(CliEval, UvFileSamplesExactlyTheGivenParameters) {
  TempDir tmp;
  const std::string uv = tmp / "uv.csv";
  write_text(uv, "surface,u,v\n# a comment\npatch,0.25,1\n0,0.1,0.30000000000000004\n0,1,0\n");
  const CliResult r =
      run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--uv", uv});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = eval_rows(r.out, "surface,u,v,x,y,z");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(parse_exact(rows[0][1]), 0.25);
  EXPECT_EQ(parse_exact(rows[1][2]), 0.30000000000000004);
  EXPECT_EQ(parse_exact(rows[2][1]), 1.0);
}

TEST(CliEval, UvFileErrorsNameFileLineAndValue) {
  TempDir tmp;
  struct Case {
    std::string text;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {"surface,u,v\n0,0.5,0.5\n0,0.5\n", {"line 3", "'0,0.5'", "expected surface,u,v"}},
      {"0,0.5,0.5,\n", {"line 1", "expected surface,u,v"}},
      {"0,0.5,0.5\n0,1.5,0.5\n", {"line 2", "u = '1.5'", "[0, 1]"}},
      {"0,0.5,-0.25\n", {"line 1", "v = '-0.25'", "[0, 1]"}},
      {"0,0.5,nan\n", {"line 1", "v = 'nan'"}},
      {"0,0.5,1e999\n", {"line 1", "v = '1e999'"}},
      {"0,zero,0.5\n", {"line 1", "u = 'zero'"}},
      {"hull,0.5,0.5\n", {"line 1", "surface = 'hull'", "0..0"}},
      {"1,0.5,0.5\n", {"line 1", "surface = '1'"}},
      {"-1,0.5,0.5\n", {"line 1", "surface = '-1'"}},
      {"# nothing but a comment\n", {"no (u,v) samples"}},
      {"", {"no (u,v) samples"}},
  };
  for (std::size_t k = 0; k < cases.size(); ++k) {
    SCOPED_TRACE(cases[k].text);
    const std::string uv = tmp / fmt::format("uv{}.csv", k);
    write_text(uv, cases[k].text);
    const std::string out = tmp / "out.csv";
    std::vector<std::string> expect = cases[k].expect;
    expect.push_back(uv);
    expect_usage_error(run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor",
                                "--uv", uv, "--out", out}),
                       expect);
    EXPECT_FALSE(fs::exists(out));
  }
  const std::string missing = tmp / "missing.csv";
  expect_usage_error(
      run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--uv", missing}),
      {missing, "cannot open"});
  // An empty name is an error, not "no --uv" (which would evaluate the default grid).
  expect_usage_error(
      run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-coxdeboor", "--uv", ""}),
      {"--uv", "the file name is empty"});
}

// ----------------------------------------------------------------------------------------- run

TEST(CliRun, WritesJsonAndCsvWithOneRowPerMeasurement) {
  TempDir tmp;
  const std::string out = tmp / "r";
  const CliResult r = run_cli({"run", "--scenes", "patch144,sphere", "--samples", "8x8",
                               "--repetitions", "1", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // Every strategy plus the six limit rows (store bandwidth, device copy, the three APIs' links,
  // the GL fragment pass), per scene.
  const std::size_t measurements = 2 * (strategy_registry().size() + 6);

  const std::vector<std::string> lines = split_lines(read_text(fs::path(out) / "results.csv"));
  ASSERT_EQ(lines.size(), 1 + measurements);
  EXPECT_EQ(lines[0], kResultsCsvHeader);
  const std::size_t columns = split_csv(kResultsCsvHeader).size();
  std::multiset<std::string> scenes;
  for (std::size_t k = 1; k < lines.size(); ++k) {
    const std::vector<std::string> row = split_csv(lines[k]);
    ASSERT_EQ(row.size(), columns) << lines[k];
    scenes.insert(row[0]);
    EXPECT_EQ(row[4], "grid");
    EXPECT_EQ(row[5], "8x8");
    if (row[1] == "cpu-coxdeboor") {
      EXPECT_EQ(row[19], "ok") << lines[k];
      EXPECT_EQ(row[6], "64");
      EXPECT_LE(parse_exact(row[18]), 64.0) << "max_ulp";
    }
    if (row[1] == "limit-store-bandwidth") {
      EXPECT_EQ(row[19], "ok") << lines[k];
      EXPECT_GT(parse_exact(row[14]), 0.0) << "throughput";
      EXPECT_EQ(row[18], "") << "a limit row has no accuracy";
    }
    // ok on the software drivers; unavailable without the API
    if (row[1] == "limit-device-copy" || row[1].starts_with("limit-link-") ||
        row[1] == "limit-gl-fragment-pass") {
      EXPECT_TRUE(row[19] == "ok" || row[19] == "unavailable") << lines[k];
    }
  }
  EXPECT_EQ(scenes.count("patch144"), measurements / 2);
  EXPECT_EQ(scenes.count("sphere"), measurements / 2);
  // The console ends with the digest: one line per scene, a ratio to the baseline measured there.
  const std::vector<std::string> out_lines = split_lines(r.out);
  ASSERT_GE(out_lines.size(), 3u) << r.out;
  EXPECT_TRUE(out_lines[out_lines.size() - 3].starts_with("digest: ")) << r.out;
  EXPECT_TRUE(out_lines[out_lines.size() - 2].starts_with("  patch144 8x8: ")) << r.out;
  EXPECT_TRUE(out_lines.back().starts_with("  sphere 8x8: ")) << r.out;
  for (std::size_t k = out_lines.size() - 2; k < out_lines.size(); ++k)
    EXPECT_NE(out_lines[k].find("x cpu-coxdeboor, "), std::string::npos) << out_lines[k];

  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  EXPECT_EQ(results["format"], "nurbsbench-results/1");
  ASSERT_TRUE(results["records"].is_array());
  EXPECT_EQ(results["records"].size(), measurements);
  EXPECT_TRUE(results["machine"].is_object());
}

// A T-spline strategy meets a NURBS scene (and the reverse) by design: the console table leaves
// those refusals out and counts them; the results files keep every record.
TEST(CliRun, SummaryLeavesOutRefusalsByKindAndCountsThem) {
  TempDir tmp;
  const std::string out = tmp / "r";
  const CliResult r = run_cli({"run", "--scenes", "patch144,tspline-tjunction", "--strategies",
                               "cpu-coxdeboor,cpu-tspline", "--samples", "4x4", "--repetitions",
                               "1", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  ASSERT_EQ(results["records"].size(), 4u);
  std::size_t refused = 0;
  for (const json& record : results["records"]) {
    // patch144 is NURBS, tspline-tjunction a T-spline: each strategy meets the other kind once.
    const bool mismatch = (record["strategy"] == "cpu-tspline") == (record["scene"] == "patch144");
    EXPECT_EQ(record["status"], mismatch ? "refused" : "ok") << record.dump();
    refused += mismatch;
  }
  ASSERT_EQ(refused, 2u);
  EXPECT_NE(r.out.find("(2 records refused by kind"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("statuses: 2 ok, 2 refused"), std::string::npos) << r.out;
  for (const std::string& line : split_lines(r.out))
    if (line.find("refused") != std::string::npos) {
      EXPECT_TRUE(line.starts_with("statuses: ") || line.starts_with("(2 records refused by kind"))
          << line;
    }
}

// The store-bandwidth ceiling is a row of the same run, selectable by name, without accuracy.
TEST(CliRun, StoreLimitRowIsMeasuredInTheSameRun) {
  TempDir tmp;
  const std::string out = tmp / "r";
  const CliResult r = run_cli(
      {"run", "--scenes", "many-4", "--strategies", "limit-store-bandwidth,cpu-coxdeboor",
       "--samples", "16x8", "--precision", "f64", "--normals", "--repetitions", "2", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  ASSERT_EQ(results["records"].size(), 2u);
  const json& limit = results["records"][0];
  EXPECT_EQ(limit["strategy"], "limit-store-bandwidth");
  EXPECT_EQ(limit["role"], "limit");
  EXPECT_EQ(limit["points"], 4 * 16 * 8);
  EXPECT_TRUE(limit["accuracy"].is_null());
  EXPECT_EQ(limit["figures"]["bytes_per_point"], 48);  // xyz + normal, doubles
  EXPECT_DOUBLE_EQ(limit["figures"]["store_bytes_per_s"].get<double>(),
                   48 * limit["throughput_pts_per_s"].get<double>());
  EXPECT_EQ(results["settings"]["strategies"][1], "limit-store-bandwidth");
  EXPECT_EQ(results["records"][1]["strategy"], "cpu-coxdeboor");
}

// Each API's host<->device link beside a strategy of that API: the row copies exactly the result's
// bytes both ways, and the report reads the strategy's read-back as a fraction of it.
TEST(CliRun, LinkLimitRowIsMeasuredInTheSameRunAndReportedAsAFraction) {
  TempDir tmp;
  const std::string out = tmp / "r";
  const CliResult r = run_cli({"run", "--scenes", "many-4", "--strategies",
                               "vk-compute,limit-link-vulkan,limit-link-opencl", "--samples",
                               "64x32", "--repetitions", "2", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  ASSERT_EQ(results["records"].size(), 3u);
  const json& vulkan = results["records"][0];
  EXPECT_EQ(vulkan["strategy"], "limit-link-vulkan");
  EXPECT_EQ(results["records"][1]["strategy"], "limit-link-opencl");
  EXPECT_EQ(results["settings"]["strategies"][1], "limit-link-vulkan");
  if (vulkan["status"] != "ok") {
    EXPECT_EQ(vulkan["status"], "unavailable") << vulkan.dump();
    return;
  }
  EXPECT_EQ(vulkan["role"], "limit");
  EXPECT_TRUE(vulkan["accuracy"].is_null());
  EXPECT_EQ(vulkan["figures"]["bytes"], 4 * 64 * 32 * 12);  // xyz, floats
  EXPECT_GT(vulkan["read_back"]["min_s"].get<double>(), 0.0);
  EXPECT_GT(vulkan["upload"]["min_s"].get<double>(), 0.0);
  const json& strategy = results["records"][2];
  ASSERT_EQ(strategy["status"], "ok") << strategy.dump();
  EXPECT_EQ(strategy["device"]["name"], vulkan["device"]["name"]);
  const std::string report = tmp / "report";
  ASSERT_EQ(run_cli({"report", "--results", out, "--out", report, "--error-images", "0"}).exit_code,
            0);
  const std::string md = read_text(fs::path(report) / "REPORT.md");
  EXPECT_NE(md.find("read_back of link"), std::string::npos) << md;
  // The strategy's row has a percentage in the column (the limit rows have '-').
  const double fraction = vulkan["read_back"]["median_s"].get<double>() /
                          strategy["read_back"]["median_s"].get<double>();
  EXPECT_NE(md.find(fmt::format("{:.1f}%", 100 * fraction)), std::string::npos) << md;
}

// The device-copy ceiling likewise, and alone: a run of only limit rows is a valid run.
TEST(CliRun, DeviceCopyLimitRowIsMeasuredInTheSameRun) {
  TempDir tmp;
  const std::string out = tmp / "r";
  const CliResult r =
      run_cli({"run", "--scenes", "many-4", "--strategies", "limit-device-copy", "--samples",
               "16x8", "--precision", "f64", "--repetitions", "2", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  ASSERT_EQ(results["records"].size(), 1u);
  const json& limit = results["records"][0];
  EXPECT_EQ(limit["strategy"], "limit-device-copy");
  EXPECT_EQ(limit["role"], "limit");
  EXPECT_EQ(limit["points"], 4 * 16 * 8);
  EXPECT_TRUE(limit["accuracy"].is_null());
  EXPECT_EQ(results["settings"]["strategies"][0], "limit-device-copy");
  if (limit["status"] == "ok") {
    EXPECT_EQ(limit["figures"]["bytes_per_point"], 24);  // xyz, doubles
    EXPECT_DOUBLE_EQ(limit["figures"]["copy_bytes_per_s"].get<double>(),
                     24 * limit["throughput_pts_per_s"].get<double>());
  } else {
    EXPECT_EQ(limit["status"], "unavailable");
    EXPECT_FALSE(limit["reason"].get<std::string>().empty());
  }
}

// Both samplings in one run: the grids, then the span grids (a study compares a strategy's modes
// on both without a run per sampling).
TEST(CliRun, GridsAndSpanGridsInOneRun) {
  TempDir tmp;
  const std::string out = tmp / "r";
  const CliResult r =
      run_cli({"run", "--scenes", "patch144", "--strategies", "cpu-coxdeboor", "--samples", "4x3",
               "--span-samples", "2", "--repetitions", "1", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  EXPECT_EQ(results["settings"]["samplings"], json({"4x3", "span2"}));
  ASSERT_EQ(results["records"].size(), 2u);
  EXPECT_EQ(results["records"][0]["points"], 12);
  EXPECT_EQ(results["records"][1]["sampling"], "span_grid");
  // The same span grid as a run given it alone.
  const std::string alone = tmp / "alone";
  ASSERT_EQ(run_cli({"run", "--scenes", "patch144", "--strategies", "cpu-coxdeboor",
                     "--span-samples", "2", "--repetitions", "1", "--out", alone})
                .exit_code,
            0);
  const json span = json::parse(read_text(fs::path(alone) / "results.json"));
  ASSERT_EQ(span["records"].size(), 1u);
  EXPECT_EQ(results["records"][1]["points"], span["records"][0]["points"]);
  EXPECT_EQ(results["records"][1]["accuracy"]["max_abs"],
            span["records"][0]["accuracy"]["max_abs"]);
}

TEST(CliRun, BadArgumentsLeaveNoOutputDirectory) {
  TempDir tmp;
  const std::string out = tmp / "r";
  struct Case {
    std::string scenes = "patch144", strategies = "cpu-coxdeboor", sampling_option = "--samples",
                sampling = "4x4", repetitions = "1", precision = "f32";
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {.scenes = "patch144,nosuch", .expect = {"'nosuch'", "neither a file nor a built-in scene"}},
      {.scenes = ",", .expect = {"--scenes", "empty"}},
      {.strategies = "cpu-nope", .expect = {"--strategies", "'cpu-nope'", "cpu-coxdeboor"}},
      {.sampling = "1x1", .expect = {"--samples", "'1x1'"}},
      {.sampling = "8x8,abc", .expect = {"--samples", "'abc'"}},
      {.sampling_option = "--span-samples", .sampling = "0", .expect = {"--span-samples", "'0'"}},
      {.sampling_option = "--span-samples", .sampling = "-1", .expect = {"--span-samples", "'-1'"}},
      {.sampling_option = "--span-samples",
       .sampling = "99999",
       .expect = {"--span-samples", "'99999'"}},
      {.sampling_option = "--span-samples", .sampling = "2,x", .expect = {"--span-samples", "'x'"}},
      {.repetitions = "0", .expect = {"--repetitions", "0"}},
      {.precision = "f16", .expect = {"--precision", "'f16'"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.expect.front());
    const CliResult r = run_cli({"run", "--scenes", c.scenes, "--strategies", c.strategies,
                                 c.sampling_option, c.sampling, "--repetitions", c.repetitions,
                                 "--precision", c.precision, "--out", out});
    expect_usage_error(r, c.expect);
    EXPECT_FALSE(fs::exists(out));
  }
  // A malformed --strategy-option is refused before the output directory is made (it was read
  // only when the first measurement started, after the results files existed).
  const CliResult r = run_cli({"run", "--scenes", "patch144", "--strategies", "cpu-coxdeboor",
                               "--samples", "4x4", "--strategy-option", "=x", "--out", out});
  expect_usage_error(r, {"--strategy-option", "KEY=VALUE"});
  EXPECT_FALSE(fs::exists(out));
}

// ----------------------------------------------------------------------------------------- lod

using RefusedCases = std::vector<std::pair<std::vector<std::string>, std::vector<std::string>>>;

// `verb --out out ARGS` for each case: a usage error naming the case's words, nothing written.
void expect_each_refused(const std::string& verb, const std::string& out,
                         const RefusedCases& cases) {
  for (const auto& [args, expect] : cases) {
    SCOPED_TRACE(expect.front());
    std::vector<std::string> argv = {verb, "--out", out};
    argv.insert(argv.end(), args.begin(), args.end());
    expect_usage_error(run_cli(argv), expect);
    EXPECT_FALSE(fs::exists(out));
  }
}

// Checked before any GL work or output: these hold in every build (the measurement itself is
// tested with glsl-deboor's GL tests).
TEST(CliLod, BadArgumentsLeaveNoOutputDirectory) {
  TempDir tmp;
  const std::string out = tmp / "lod";
  const RefusedCases cases = {
      {{"--scene", "many-4"}, {"--scene", "'many-4'", "4 surfaces"}},
      {{"--scene", "nosuch"}, {"'nosuch'", "neither a file nor a built-in scene"}},
      {{"--samples", "100x100"}, {"--samples", "100x100", "halve 3 times", "multiples of 8"}},
      {{"--samples", "64x64", "--levels", "7"}, {"--samples", "64x64", "halve 7 times"}},
      {{"--levels", "0"}, {"--levels", "0", "1..8"}},
      {{"--repetitions", "0"}, {"--repetitions", "0"}},
      {{"--samples", "1x1"}, {"--samples", "'1x1'"}},
      // A file where the picture directory goes (or a build without OpenImageIO): refused too.
      {{"--images", tmp / "a-file"}, {"--images", "a-file"}},
  };
  write_text(fs::path(tmp / "a-file"), "not a directory");
  expect_each_refused("lod", out, cases);
}

// ------------------------------------------------------------------------------- camera-path

// Checked before any GL work or output, so these hold in every build (the fly-in itself is
// tested in camera_path_test.cpp).
TEST(CliCameraPath, BadArgumentsLeaveNoOutputDirectory) {
  TempDir tmp;
  const std::string out = tmp / "camera";
  const RefusedCases cases = {
      {{"--frames", "1"}, {"--frames", "1", "2..10000"}},
      {{"--frames", "abc"}, {"--frames"}},
      {{"--viewport", "8x8"}, {"--viewport", "'8x8'", "16..8192"}},
      {{"--viewport", "64x64,32x32"}, {"--viewport", "one WxH"}},
      {{"--viewport", "wide"}, {"--viewport", "'wide'"}},
      {{"--pixels-per-sample", "0"}, {"--pixels-per-sample", "0.25..1024"}},
      {{"--pixels-per-sample", "nan"}, {"--pixels-per-sample"}},
      {{"--min-samples", "9", "--max-samples", "8"}, {"--min-samples = 9", "--max-samples = 8"}},
      {{"--fixed-samples", "1x4"}, {"--fixed-samples", "'1x4'"}},
      {{"--scenes", "nosuch"}, {"'nosuch'", "neither a file nor a built-in scene"}},
      {{"--scenes", "tspline-tjunction"}, {"tspline-tjunction", "T-spline"}},
      {{"--images", tmp / "a-file"}, {"--images", "a-file"}},
  };
  write_text(fs::path(tmp / "a-file"), "not a directory");
  expect_each_refused("camera-path", out, cases);
}

TEST(CliRun, DeformingRecordsFrameTimesAndLastFrameAccuracy) {
  TempDir tmp;
  const std::string out = tmp / "r";
  const CliResult r =
      run_cli({"run", "--scenes", "patch144", "--strategies", "cpu-bezier,cpu-coxdeboor",
               "--samples", "8x8", "--deforming", "3", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("deforming, 3 frames"), std::string::npos) << r.out;
  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  EXPECT_EQ(results["settings"]["deforming_frames"], 3);
  ASSERT_EQ(results["records"].size(), 2u);  // no store-limit row in this mode
  for (const json& rec : results["records"]) {
    ASSERT_EQ(rec["status"], "ok") << rec.dump();
    EXPECT_TRUE(rec["extra_phases"].contains("frame")) << rec.dump();
    EXPECT_EQ(rec["figures"]["frames"], 3);
    EXPECT_LE(rec["accuracy"]["max_ulp"].get<double>(), 32.0);
    // cpu-bezier updates its control points; cpu-coxdeboor is prepared again, and says so.
    const bool updates = rec["strategy"] == "cpu-bezier";
    EXPECT_EQ(rec["extra_phases"].contains("frame_update"), updates) << rec.dump();
    EXPECT_EQ(rec["extra_phases"].contains("frame_prepare"), !updates) << rec.dump();
  }
}

TEST(CliRun, BadDeformingFrameCountsAreRefused) {
  TempDir tmp;
  const std::string out = tmp / "r";
  for (const std::string bad : {"-1", "abc", "1000001"}) {
    SCOPED_TRACE(bad);
    expect_usage_error(run_cli({"run", "--scenes", "patch144", "--strategies", "cpu-bezier",
                                "--deforming", bad, "--out", out}),
                       {"--deforming"});
    EXPECT_FALSE(fs::exists(out));
  }
}

// -------------------------------------------------------------------------------------- memory

TEST(CliMemory, TextHasOneRowPerSceneAndStatesItsUnits) {
  const CliResult r = run_cli({"memory", "--scenes", "patch144,teapot"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), 4u) << r.out;  // header, two scenes, the units line
  EXPECT_NE(lines[0].find("KSQuads"), std::string::npos);
  EXPECT_NE(lines[0].find("Bezier#CP"), std::string::npos);
  EXPECT_TRUE(lines[1].starts_with("patch144")) << lines[1];
  EXPECT_NE(lines[1].find(" 1296 "), std::string::npos) << lines[1];
  EXPECT_NE(lines[0].find("shared#CP"), std::string::npos);
  EXPECT_NE(lines[1].find(" 784 "), std::string::npos) << lines[1];  // 28 x 28 shared once
  EXPECT_TRUE(lines[2].starts_with("teapot")) << lines[2];
  EXPECT_NE(lines[3].find("16 bytes"), std::string::npos) << lines[3];
}

TEST(CliMemory, JsonForEveryDefaultScene) {
  const CliResult r = run_cli({"memory", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);
  EXPECT_EQ(doc["format"], "nurbsbench-memory/1");
  std::set<std::string> scenes;
  for (const json& row : doc["rows"]) {
    scenes.insert(row["scene"].get<std::string>());
    EXPECT_GE(row["bezier_control_points"].get<double>(), 1.0);
    EXPECT_EQ(row["ksquads"], row["bezier_patches"]);
    EXPECT_LE(row["bezier_shared_control_points"], row["bezier_control_points"]);
  }
  EXPECT_TRUE(scenes.count("patch144") && scenes.count("teapot") && scenes.count("duck"));
  EXPECT_FALSE(scenes.count("many-4096"));  // 'default', as in run
}

TEST(CliMemory, BadScenesAreExitTwoWithOneLine) {
  for (const std::string bad : {"patch144,nosuch", "many-0"}) {
    const CliResult r = run_cli({"memory", "--scenes", bad});
    expect_usage_error(r, {"neither a file nor a built-in scene"});
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  expect_usage_error(run_cli({"memory", "--scenes", ","}), {"--scenes", "empty"});
  expect_usage_error(run_cli({"memory", "--bogus"}), {"--bogus"});
}

// --------------------------------------------------------------------------------------- trims

// The built-in trimmed-plate's face in closed form, per sample of a CSV row's (u, v).
double plate_distance(const std::vector<std::string>& row) {
  return trimmed_plate_signed_distance(TrimmedPlateShape{}, parse_exact(row[1]),
                                       parse_exact(row[2]));
}

TEST(CliTrim, EvalWritesTheStrategysInsideColumn) {
  TempDir tmp;
  const std::string out = tmp / "p.csv";
  const CliResult r = run_cli({"eval", "--scene", "trimmed-plate", "--strategy", "cpu-coxdeboor",
                               "--samples", "17x13", "--normals", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rows = eval_rows(read_text(out), "surface,u,v,x,y,z,nx,ny,nz,inside");
  ASSERT_EQ(rows.size(), 17u * 13u);
  std::size_t inside = 0;
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 10u);
    const double d = plate_distance(row);
    ASSERT_GT(std::abs(d), 1e-9) << "no sample of this grid lies on the boundary";
    EXPECT_EQ(row[9], d < 0 ? "1" : "0") << row[1] << "," << row[2];
    inside += d < 0;
  }
  // The accuracy line says what the errors are over, and the classification's score.
  EXPECT_NE(r.err.find(fmt::format("errors over the {} samples inside the faces", inside)),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("0 misclassified outside the band"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("band 1e-07"), std::string::npos) << r.err;

  // A strategy that does not trim: no column, and the accuracy line says so.
  const CliResult plain = run_cli({"eval", "--scene", "trimmed-plate", "--strategy", "cpu-horner",
                                   "--samples", "17x13", "--trim-band", "0.001"});
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  EXPECT_EQ(eval_rows(plain.out, "surface,u,v,x,y,z").size(), 17u * 13u);
  EXPECT_NE(plain.err.find("untrimmed"), std::string::npos) << plain.err;
  EXPECT_NE(plain.err.find("band 0.001"), std::string::npos) << plain.err;
}

TEST(CliTrim, RunScoresTrimmedScenesWithTheGivenBand) {
  TempDir tmp;
  const std::string out = tmp / "r";
  const CliResult r = run_cli({"run", "--scenes", "trimmed-plate,patch144", "--strategies",
                               "cpu-coxdeboor,cpu-horner", "--samples", "33x33", "--repetitions",
                               "2", "--trim-band", "0.01", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // By the closed form at u, v = k/32: samples inside, and samples within the band of 0.01 x the
  // domain diagonal (sqrt 2) -- bounded by 1% either way, the stated accuracy of the reference's
  // distance.
  std::size_t inside = 0, near_low = 0, near_high = 0;
  const double band = 0.01 * std::sqrt(2.0);
  for (int a = 0; a <= 32; ++a)
    for (int b = 0; b <= 32; ++b) {
      const double d = trimmed_plate_signed_distance(TrimmedPlateShape{}, a / 32.0, b / 32.0);
      inside += d < 0;
      near_low += std::abs(d) < 0.99 * band;
      near_high += std::abs(d) < 1.01 * band;
    }
  ASSERT_GT(near_low, 0u) << "the band must hold some samples for the test to mean anything";

  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  EXPECT_EQ(results["settings"]["trim_band"], 0.01);
  ASSERT_EQ(results["records"].size(), 4u);
  for (const json& rec : results["records"]) {
    SCOPED_TRACE(rec.dump());
    ASSERT_EQ(rec["status"], "ok");
    if (rec["scene"] == "patch144") {
      EXPECT_FALSE(rec.contains("trimming"));
      EXPECT_FALSE(rec["accuracy"].contains("trim"));
      continue;
    }
    const json& trim = rec["accuracy"]["trim"];
    EXPECT_EQ(trim["band"], 0.01);
    EXPECT_EQ(trim["inside_samples"], inside);
    EXPECT_GE(trim["boundary_samples"].get<std::size_t>(), near_low);
    EXPECT_LE(trim["boundary_samples"].get<std::size_t>(), near_high);
    const bool classifies = rec["strategy"] == "cpu-coxdeboor";
    EXPECT_EQ(rec["trimming"], classifies ? "classified" : "untrimmed");
    EXPECT_EQ(rec.contains("extra_phases") && rec["extra_phases"].contains("classify"), classifies);
    EXPECT_EQ(trim.contains("misclassified"), classifies);
    if (classifies) {
      EXPECT_EQ(trim["misclassified"], 0);
    }
  }
  // The CSV's trim columns, and the summary's trim column.
  const std::vector<std::string> lines = split_lines(read_text(fs::path(out) / "results.csv"));
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0], kResultsCsvHeader);
  const std::vector<std::string> first = split_csv(lines[1]);  // cpu-coxdeboor on trimmed-plate
  ASSERT_EQ(first.size(), split_csv(kResultsCsvHeader).size());
  EXPECT_EQ(first[21], "classified");
  EXPECT_EQ(first[22], "0.01");
  EXPECT_EQ(first[23], std::to_string(inside));
  EXPECT_EQ(first[25], "0");
  EXPECT_NE(r.out.find("untrimmed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("0 misclassified (0)"), std::string::npos) << r.out;
}

// A scene file (nurbs-scene/2) with a trimmed, reversed face: the hand-classified plate of
// tests/harness/plates.h, so every expected value here is known without the classifier.
TEST(CliTrim, SceneFileWithAReversedTrimmedFace) {
  TempDir tmp;
  Scene scene = trimmed_plate();
  scene.surfaces[0].reversed = true;
  const std::string file = tmp / "plate.json", csv = tmp / "p.csv";
  write_text(file, scene_to_json(scene));

  const CliResult eval = run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor",
                                  "--samples", "9x9", "--normals", "--out", csv});
  ASSERT_EQ(eval.exit_code, 0) << eval.err;
  const auto rows = eval_rows(read_text(csv), "surface,u,v,x,y,z,nx,ny,nz,inside");
  ASSERT_EQ(rows.size(), 81u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.size(), 10u);
    EXPECT_EQ(row[9], hand_inside(parse_exact(row[1]), parse_exact(row[2])) ? "1" : "0");
    // S_u x S_v = +z on the plate; the reversed face's normal, as written, is -z.
    EXPECT_EQ(parse_exact(row[8]), -1.0) << row[1] << "," << row[2];
  }
  EXPECT_NE(eval.err.find("errors over the 40 samples inside the faces"), std::string::npos)
      << eval.err;
  EXPECT_NE(eval.err.find("normals within 0 deg"), std::string::npos) << eval.err;

  // 0.04 x sqrt(2): exactly the 12 samples 0.05 beside the hole are boundary samples.
  const std::string out = tmp / "r";
  const CliResult run =
      run_cli({"run", "--scenes", file, "--strategies", "cpu-coxdeboor,cpu-horner", "--samples",
               "9x9", "--repetitions", "1", "--normals", "--trim-band", "0.04", "--out", out});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const json results = json::parse(read_text(fs::path(out) / "results.json"));
  ASSERT_EQ(results["records"].size(), 2u);
  for (const json& rec : results["records"]) {
    SCOPED_TRACE(rec.dump());
    ASSERT_EQ(rec["status"], "ok");
    EXPECT_EQ(rec["accuracy"]["trim"]["inside_samples"], 40);
    EXPECT_EQ(rec["accuracy"]["trim"]["boundary_samples"], 12);
    EXPECT_LT(rec["accuracy"]["max_normal_angle_deg"].get<double>(), 1e-3);
  }
  EXPECT_EQ(results["records"][0]["accuracy"]["trim"]["misclassified"], 0);
  EXPECT_EQ(results["records"][1]["trimming"], "untrimmed");
}

TEST(CliTrim, BadTrimBandIsExitTwoAndWritesNothing) {
  TempDir tmp;
  const std::string out = tmp / "r", csv = tmp / "p.csv";
  for (const std::string bad : {"-0.1", "1", "nan", "inf", "abc", "0.1x", ""}) {
    SCOPED_TRACE(bad);
    expect_usage_error(run_cli({"run", "--scenes", "trimmed-plate", "--strategies", "cpu-coxdeboor",
                                "--samples", "4x4", "--trim-band", bad, "--out", out}),
                       {"--trim-band", "'" + bad + "'"});
    EXPECT_FALSE(fs::exists(out));
    expect_usage_error(run_cli({"eval", "--scene", "trimmed-plate", "--strategy", "cpu-coxdeboor",
                                "--samples", "4x4", "--trim-band", bad, "--out", csv}),
                       {"--trim-band", "'" + bad + "'"});
    EXPECT_FALSE(fs::exists(csv));
  }
}

// --------------------------------------------------------------------------------------- check

class CliCheck : public ::testing::Test {
 protected:
  // Made once per build and shared by every case (each runs in a process of its own).
  static void SetUpTestSuite() {
    const SharedCliOutput run =
        shared_cli_output({"run", "--scenes", "patch144,sphere", "--strategies", "cpu-coxdeboor",
                           "--samples", "8x8", "--repetitions", "1"});
    ASSERT_EQ(run.result.exit_code, 0) << run.result.err;
    results_ = run.directory;
  }

  CliResult check(const std::string& gates_json) {
    const std::string gates = tmp_ / "gates.json";
    write_text(gates, gates_json);
    return run_cli({"check", "--gates", gates, "--results", results_.string()});
  }
  // The measured value of one record, as check prints it.
  static std::string measured(const std::string& scene, const std::string& metric) {
    const json results = json::parse(read_text(results_ / "results.json"));
    for (const json& r : results["records"])
      if (r["scene"] == scene) return fmt::format("{:.6g}", r["accuracy"][metric].get<double>());
    ADD_FAILURE() << "no record for " << scene;
    return "";
  }

  static std::filesystem::path results_;
  TempDir tmp_;
};
std::filesystem::path CliCheck::results_;

TEST_F(CliCheck, GatesThatHoldExitZero) {
  const CliResult r = check(R"([
    {"strategy": "cpu-coxdeboor", "scene": "patch144", "metric": "max_ulp", "max": 64},
    {"strategy": "cpu-coxdeboor", "scene": "sphere", "metric": "max_abs", "max": 1e-4, "note": "why"}
  ])");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("2 gates checked against 2 results: 0 violations"), std::string::npos)
      << r.out;
}

TEST_F(CliCheck, ViolatedGateExitsOneAndNamesTheMeasuredValue) {
  const CliResult r = check(R"([
    {"strategy": "cpu-coxdeboor", "scene": "patch144", "metric": "max_abs", "max": 1e-12},
    {"strategy": "cpu-coxdeboor", "scene": "sphere", "metric": "max_abs", "max": 1}
  ])");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  const std::vector<std::string> lines = split_lines(r.out);
  ASSERT_EQ(lines.size(), 2u) << r.out;
  EXPECT_TRUE(lines[0].starts_with("FAIL cpu-coxdeboor on patch144")) << lines[0];
  EXPECT_NE(lines[0].find("max_abs = " + measured("patch144", "max_abs") + " exceeds 1e-12"),
            std::string::npos)
      << lines[0];
  EXPECT_NE(lines[0].find("worst sample: surface 0, u = "), std::string::npos) << lines[0];
  EXPECT_NE(lines[1].find("1 violation"), std::string::npos) << lines[1];
}

TEST_F(CliCheck, GateMatchingNothingIsAViolation) {
  const CliResult r =
      check(R"([{"strategy": "gl-*", "scene": "teapot", "metric": "max_abs", "max": 1}])");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(
      r.out.find(
          "FAIL gate {strategy: gl-*, scene: teapot, metric: max_abs} matched no measured result"),
      std::string::npos)
      << r.out;
}

TEST_F(CliCheck, GlobsSelectStrategiesAndScenes) {
  // s?here matches sphere only, so only the sphere record can violate.
  CliResult r =
      check(R"([{"strategy": "cpu-*", "scene": "s?here", "metric": "max_rel", "max": 0}])");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FAIL cpu-coxdeboor on sphere"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("patch144"), std::string::npos) << r.out;
  // * and [..] match both records: two violations.
  r = check(R"([{"strategy": "*", "scene": "[ps]*", "metric": "max_rel", "max": 0}])");
  EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FAIL cpu-coxdeboor on sphere"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("FAIL cpu-coxdeboor on patch144"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("2 violations"), std::string::npos) << r.out;
  // A glob that matches, with a bound that holds.
  r = check(R"([{"strategy": "cpu-cox*", "scene": "*", "metric": "max_ulp", "max": 64}])");
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
}

TEST_F(CliCheck, MalformedGatesFileIsExitTwo) {
  struct Case {
    std::string text;
    std::vector<std::string> expect;
  };
  const std::vector<Case> cases = {
      {R"([{"strategy": "cpu-coxdeboor")", {"not valid JSON"}},
      {"\x89PNG\r\n", {"not valid JSON"}},
      {R"({"strategy": "cpu-coxdeboor"})", {"list of gates"}},
      {R"([42])", {"gate [0]", "object"}},
      {R"([{"strategy": "a", "scene": "b", "metric": "max_abs", "max": 1, "maxx": 2}])",
       {"gate [0]", "maxx", "unknown key"}},
      {R"([{"strategy": "a", "scene": "b", "metric": "max_abs", "max": 1},
           {"strategy": "a", "scene": "b", "metric": "max_abss", "max": 1}])",
       {"gate [1]", "max_abss", "unknown metric"}},
      {R"([{"strategy": "a", "scene": "b", "metric": "max_abs", "max": "1e-3"}])",
       {"gate [0]", "max", "number"}},
      {R"([{"scene": "b", "metric": "max_abs", "max": 1}])", {"gate [0]", "strategy", "(missing)"}},
      {R"([{"strategy": "a", "scene": "b", "metric": "max_abs"}])",
       {"gate [0]", "max", "(missing)"}},
      // The strict parser every reader of a user's JSON shares (scenes/json_strict.h): a repeated
      // key would silently mean its last value, and nesting is bounded.
      {R"([{"strategy": "a", "scene": "b", "metric": "max_abs", "max": 1, "max": 2}])",
       {"[0].max", "duplicate key"}},
      {std::string(100, '[') + std::string(100, ']'), {"nesting deeper than 64"}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const CliResult r = check(c.text);
    std::vector<std::string> expect = c.expect;
    expect.push_back(tmp_ / "gates.json");
    expect_usage_error(r, expect);
  }
  const std::string missing = tmp_ / "missing.json";
  expect_usage_error(run_cli({"check", "--gates", missing, "--results", results_.string()}),
                     {missing, "cannot read gates file"});
}

TEST_F(CliCheck, MissingResultsIsExitTwo) {
  const std::string gates = tmp_ / "gates.json";
  write_text(gates, R"([{"strategy": "*", "scene": "*", "metric": "max_abs", "max": 1}])");
  const std::string missing = tmp_ / "no-results";
  expect_usage_error(run_cli({"check", "--gates", gates, "--results", missing}), {missing});
}

}  // namespace
}  // namespace nurbs::test
