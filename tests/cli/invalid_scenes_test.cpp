// Every file in scenes/invalid/ is fed to the CLI as a user would: `eval`, `run` and `scene` must
// each refuse it with exit code 2 and one stderr line naming the file and everything its
// .expect file lists (field, index, value, surface), and must leave no output behind. Adding a
// case is adding a <case>.json with its <case>.expect (one required substring per line). Inputs
// too big or too odd to commit (deep nesting, an oversized file, values beyond float's range) are
// generated here.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "run_cli.h"
#include "scenes/scene_json.h"
#include "strategies/strategy.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;

const fs::path kInvalidDir = fs::path(NURBSBENCH_SOURCE_DIR) / "scenes" / "invalid";

std::vector<std::string> invalid_cases() {
  std::vector<std::string> names;
  for (const fs::directory_entry& e : fs::directory_iterator(kInvalidDir))
    if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> expected_substrings(const std::string& name) {
  std::vector<std::string> out;
  for (const std::string& line : split_lines(read_text(kInvalidDir / (name + ".expect"))))
    if (!line.empty()) out.push_back(line);
  return out;
}

// The assertions shared by every verb and every bad input: exit 2, one line, the file named and
// every expected substring present.
void expect_rejection(const CliResult& r, const std::string& file,
                      const std::vector<std::string>& substrings) {
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(is_one_error_line(r.err)) << "stderr:\n" << r.err;
  EXPECT_TRUE(r.err.starts_with("nurbsbench: error: ")) << r.err;
  EXPECT_NE(r.err.find(file), std::string::npos) << "the file is not named: " << r.err;
  for (const std::string& s : substrings)
    EXPECT_NE(r.err.find(s), std::string::npos) << "missing '" << s << "' in: " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(InvalidScenesFolder, EveryCaseHasItsExpectation) {
  for (const fs::directory_entry& e : fs::directory_iterator(kInvalidDir)) {
    const fs::path p = e.path();
    if (p.filename() == "README.md") continue;
    ASSERT_TRUE(p.extension() == ".json" || p.extension() == ".expect") << p;
    const fs::path sibling =
        fs::path(p).replace_extension(p.extension() == ".json" ? ".expect" : ".json");
    EXPECT_TRUE(fs::exists(sibling)) << p << " has no " << sibling.filename();
    if (p.extension() == ".json") {
      EXPECT_FALSE(expected_substrings(p.stem().string()).empty()) << p;
    }
  }
  // One case per validation rule (docs/design.md §Data model) plus the malformed-JSON cases.
  EXPECT_GE(invalid_cases().size(), 40u);
}

enum class Verb { eval, run, scene };
constexpr Verb kVerbs[] = {Verb::eval, Verb::run, Verb::scene};

// `verb` run on `file` as a user would, its output named under `tmp`: it must refuse the file
// with exit 2 and one line naming the file and every substring, and create no output.
void expect_verb_refuses(Verb verb, const std::string& file,
                         const std::vector<std::string>& substrings, const TempDir& tmp) {
  std::vector<std::string> args;
  std::string out;
  switch (verb) {
    case Verb::eval:
      out = tmp / "out.csv";
      args = {"eval", "--scene", file, "--strategy", "cpu-coxdeboor", "--out", out};
      break;
    case Verb::run:
      out = tmp / "r";
      args = {"run",
              "--scenes",
              "patch144," + file,
              "--strategies",
              "cpu-coxdeboor",
              "--samples",
              "4x4",
              "--repetitions",
              "1",
              "--out",
              out};
      break;
    case Verb::scene:
      out = tmp / "copy.json";
      args = {"scene", file, "--out", out};
      break;
  }
  SCOPED_TRACE(args[0]);
  expect_rejection(run_cli(args, {kRejectionMemoryLimit}), file, substrings);
  EXPECT_FALSE(fs::exists(out));
}

class InvalidScene : public ::testing::TestWithParam<std::string> {
 protected:
  std::string file() const { return (kInvalidDir / (GetParam() + ".json")).string(); }
  TempDir tmp_;
};

TEST_P(InvalidScene, EvalRefusesWithOneLineAndWritesNothing) {
  expect_verb_refuses(Verb::eval, file(), expected_substrings(GetParam()), tmp_);
  EXPECT_TRUE(fs::is_empty(tmp_.path())) << "no temporary or partial file may be left";
}

TEST_P(InvalidScene, RunRefusesBeforeCreatingTheOutputDirectory) {
  expect_verb_refuses(Verb::run, file(), expected_substrings(GetParam()), tmp_);
}

TEST_P(InvalidScene, SceneVerbRefusesAndWritesNothing) {
  expect_verb_refuses(Verb::scene, file(), expected_substrings(GetParam()), tmp_);
}

INSTANTIATE_TEST_SUITE_P(Files, InvalidScene, ::testing::ValuesIn(invalid_cases()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

// 4e9 control points: refused from the counts alone, before the loader allocates anything. The
// folder test above runs it under the same limit; this one states the point on its own.
TEST(InvalidScene, AbsurdCountIsRefusedUnderAMemoryLimit) {
  if (!memory_limit_supported()) GTEST_SKIP() << "no address-space limit under ASan";
  TempDir tmp;
  const std::string file = (kInvalidDir / "count-absurd-product.json").string();
  const CliResult r =
      run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor", "--out", tmp / "o.csv"},
              {kRejectionMemoryLimit});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("count_u * count_v = 4294967296 exceeds"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
}

// Bytes that are not JSON text at all (binary headers, invalid UTF-8, NUL). Generated here
// rather than committed as binary files.
TEST(InvalidScene, NonJsonBytesAreRefused) {
  TempDir tmp;
  const std::vector<std::pair<std::string, std::string>> inputs = {
      {"elf.json", std::string("\x7f"
                               "ELF\x02\x01\x01\x00\x00\xff\xfe\n\r",
                               13)},
      {"invalid-utf8.json", std::string("{\"format\": \"nurbs\xff\xfe\"}")},
      {"nul.json", std::string("\0\0\0\0", 4)},
      {"png.json", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16)},
      {"text.json", "this is not a scene\n"},
  };
  for (const auto& [name, bytes] : inputs) {
    SCOPED_TRACE(name);
    const std::string file = tmp / name;
    write_text(file, bytes);
    const std::string out = tmp / "out.csv";
    const CliResult r =
        run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor", "--out", out},
                {kRejectionMemoryLimit});
    expect_rejection(r, file, {"not valid JSON"});
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST(InvalidScene, MissingFileIsNamed) {
  TempDir tmp;
  const std::string file = tmp / "no-such-dir/scene.json";
  const CliResult r = run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor"});
  // Not a file, so it is looked up as a built-in name: the message lists the valid ones.
  expect_rejection(r, file, {"neither a file nor a built-in scene", "patch144", "many-N"});
}

// ----------------------------------------------------------------- inputs the test generates

// 300000 nested arrays crashed the CLI with a stack overflow before the parser bounded them.
TEST(HardenedInput, DeepNestingIsRefusedByEveryVerb) {
  TempDir tmp;
  const std::string file = tmp / "deep.json";
  constexpr std::size_t kLevels = 300000;
  write_text(file, R"({"format": "nurbs-scene/1", "surfaces": )" + std::string(kLevels, '[') +
                       std::string(kLevels, ']') + "}");
  for (Verb verb : kVerbs)
    expect_verb_refuses(verb, file, {"surfaces[0][0]", "nesting deeper than 64 levels"}, tmp);
}

// A sparse file one byte over the limit: refused from its size, never read.
TEST(HardenedInput, OversizedSceneFileIsRefusedBeforeReading) {
  TempDir tmp;
  const std::string file = tmp / "huge.json";
  write_text(file, "{");
  fs::resize_file(file, kMaxSceneFileBytes + 1);
  for (Verb verb : kVerbs)
    expect_verb_refuses(verb, file,
                        {fmt::format("file size {} bytes exceeds the limit of {} bytes",
                                     kMaxSceneFileBytes + 1, kMaxSceneFileBytes)},
                        tmp);
}

// ------------------------------------------------------------------ values out of float's range

Surface bilinear(std::string name) {
  Surface s;
  s.name = std::move(name);
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 1}};
  s.weights = {1, 1, 1, 1};
  return s;
}

struct RangeCase {
  std::string name;
  std::function<void(Surface&)> flaw;  // applied to the second surface, 'p'
  std::vector<std::string> reason;     // substrings of the refusal
  bool f64_too = false;                // out of double's range as well
};

// Valid scenes (finite doubles) whose values float32 cannot hold: --precision f32 must refuse
// them by name, `eval` with exit 2, `run` as a `refused` record; --precision f64 evaluates them.
TEST(PrecisionRange, F32RefusesWhatFloatCannotHold) {
  const std::vector<RangeCase> cases = {
      {"coordinate",
       [](Surface& s) { s.points[3][1] = 1e39; },
       {"points[3][1] = 1e+39", "beyond float32's largest"}},
      {"knot",
       [](Surface& s) {
         s.knots_u = {0, 0, 1e39, 1e39};
       },
       {"knots_u[2] = 1e+39"}},
      {"weight-subnormal",
       [](Surface& s) { s.weights[2] = 1e-320; },
       {"weights[2] = 1e-320", "below float32's smallest normal number"},
       true},
      {"weight-below-flt-min",
       [](Surface& s) { s.weights[2] = 1e-39; },
       {"weights[2] = 1e-39", "below float32's smallest normal number"}},
      {"weighted-coordinate",
       [](Surface& s) {
         s.weights[1] = 1e30;
         s.points[1][0] = 1e10;
       },
       {"points[1][0] = 10000000000", "times its weight 1e+30 is 1e+40"}},
  };
  TempDir tmp;
  std::vector<std::string> files;
  for (const RangeCase& c : cases) {
    SCOPED_TRACE(c.name);
    Scene scene{c.name, "", {bilinear("good"), bilinear("p")}};
    c.flaw(scene.surfaces[1]);
    const std::string file = tmp / (c.name + ".json");
    write_text(file, scene_to_json(scene));
    files.push_back(file);
    const CliResult f32 =
        run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor", "--samples", "4x4",
                 "--precision", "f32", "--out", tmp / "f32.csv"});
    EXPECT_EQ(f32.exit_code, 2) << f32.err;
    EXPECT_TRUE(is_one_error_line(f32.err)) << f32.err;
    EXPECT_NE(f32.err.find("refuses scene " + c.name + ": surface 'p' (#1): "), std::string::npos)
        << f32.err;
    for (const std::string& s : c.reason)
      EXPECT_NE(f32.err.find(s), std::string::npos) << "missing '" << s << "' in: " << f32.err;
    EXPECT_FALSE(fs::exists(tmp / "f32.csv"));
    const CliResult f64 =
        run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor", "--samples", "4x4",
                 "--precision", "f64", "--out", tmp / "f64.csv"});
    EXPECT_EQ(f64.exit_code, c.f64_too ? 2 : 0) << f64.err;
    if (c.f64_too) {
      EXPECT_NE(f64.err.find("below float64's smallest normal number"), std::string::npos)
          << f64.err;
    }
  }

  const std::string out = tmp / "r";
  const CliResult run = run_cli({"run", "--scenes", fmt::format("{}", fmt::join(files, ",")),
                                 "--strategies", "cpu-coxdeboor", "--samples", "4x4",
                                 "--repetitions", "1", "--precision", "f32", "--out", out});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json results = nlohmann::json::parse(read_text(fs::path(out) / "results.json"));
  ASSERT_EQ(results.at("records").size(), cases.size());
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const nlohmann::json& record = results["records"][k];
    SCOPED_TRACE(cases[k].name);
    EXPECT_EQ(record.at("scene"), cases[k].name);
    EXPECT_EQ(record.at("status"), "refused");
    const std::string reason = record.at("reason");
    for (const std::string& s : cases[k].reason)
      EXPECT_NE(reason.find(s), std::string::npos) << "missing '" << s << "' in: " << reason;
  }
}

// A trim curve's control points are float32 values too, for the strategies that trim.
TEST(PrecisionRange, F32RefusesTrimPointsBeyondFloat) {
  Surface face = bilinear("face");
  // A tolerance of 1e40 lets the point 1e39 pass validation (within it of the domain).
  TrimLoop loop;
  const std::vector<Point2> corners = {{0.25, 0.25}, {1e39, 0.25}, {0.5, 0.75}};
  for (std::size_t k = 0; k < 3; ++k)
    loop.curves.push_back(TrimCurve{1, {0, 0, 1, 1}, {corners[k], corners[(k + 1) % 3]}, {1, 1}});
  face.trim = Trim{"even-odd", 1e40, {loop}};
  TempDir tmp;
  const std::string file = tmp / "trim.json";
  write_text(file, scene_to_json(Scene{"trim", "", {face}}));
  const CliResult r = run_cli({"eval", "--scene", file, "--strategy", "cpu-coxdeboor", "--samples",
                               "4x4", "--out", tmp / "o.csv"});
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_TRUE(is_one_error_line(r.err)) << r.err;
  EXPECT_NE(r.err.find("surface 'face' (#0): trim.loops[0].curves[0].points[1][0] = 1e+39: "
                       "beyond float32's largest"),
            std::string::npos)
      << r.err;
}

// The rule's edges, asked of refusal_reason() directly: float's own largest number and smallest
// normal pass, the next double beyond each is refused.
TEST(PrecisionRange, FloatsOwnLimitsPassAndTheNextDoubleDoesNot) {
  const double largest = std::numeric_limits<float>::max();
  const double smallest = std::numeric_limits<float>::min();
  const EvalRequest f32{Sampling{}, Precision::f32, false};
  const auto refusal = [&](const std::function<void(Surface&)>& change) {
    Scene scene{"edge", "", {bilinear("p")}};
    change(scene.surfaces[0]);
    return refusal_reason(Capabilities{}, scene, f32);
  };
  EXPECT_FALSE(refusal([&](Surface& s) { s.points[0][2] = -largest; }));
  EXPECT_TRUE(refusal([&](Surface& s) { s.points[0][2] = -std::nextafter(largest, 1e300); }));
  EXPECT_FALSE(refusal([&](Surface& s) { s.weights[0] = smallest; }));
  EXPECT_TRUE(refusal([&](Surface& s) { s.weights[0] = std::nextafter(smallest, 0.0); }));
  // w * x = float's largest exactly passes (halving and doubling are exact); twice it does not.
  EXPECT_FALSE(refusal([&](Surface& s) {
    s.weights[3] = 2;
    s.points[3][0] = largest / 2;
  }));
  EXPECT_TRUE(refusal([&](Surface& s) {
    s.weights[3] = 2;
    s.points[3][0] = largest;
  }));
  // Tiny coordinates are no reason: they flush to 0, an error below float's smallest normal.
  EXPECT_FALSE(refusal([&](Surface& s) { s.points[1][1] = 1e-300; }));
}

}  // namespace
}  // namespace nurbs::test
