// Evaluator plugins (harness/plugins/plugin.h, issue 31) in this process: the file hash, the
// registry of added strategies, what an unusable library becomes, and -- through echo_plugin.cpp,
// which writes back a digest of its input -- that the adapter hands a plugin the scene, samples,
// options and aligned buffers the header promises, and maps its errors. The plugins are exercised
// end to end (install, out-of-tree build, run, eval, check) by tests/plugins/plugins_test.sh.
#include "harness/plugins/plugin.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <tuple>

#include "reference/tspline.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "scenes/deforming.h"

namespace nurbs {
namespace {

namespace fs = std::filesystem;

// The probe runs in a child of the measurement server, which is the CLI binary (this test's own
// binary does not know the hidden verb).
IsolationSettings probe_settings() {
  IsolationSettings settings;
  settings.executable = NURBSBENCH_CLI;
  settings.timeout_s = 10;
  return settings;
}

// In a folder of this process's own: the file name is what an unusable plugin is named after.
fs::path write_temp(const std::string& name, const std::string& bytes) {
  const fs::path folder =
      fs::temp_directory_path() / ("nurbsbench-plugin-test-" + std::to_string(::getpid()));
  fs::create_directories(folder);
  std::ofstream(folder / name, std::ios::binary) << bytes;
  return folder / name;
}

TEST(PluginTest, Sha256MatchesTheFipsVectors) {
  // FIPS 180-2 appendix B.1 and the empty message.
  const fs::path abc = write_temp("abc", "abc");
  EXPECT_EQ(file_sha256(abc), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const fs::path empty = write_temp("empty", "");
  EXPECT_EQ(file_sha256(empty), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  // B.2: 448 bits, across the padding boundary.
  const fs::path two =
      write_temp("two", "abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq");
  EXPECT_EQ(file_sha256(two), "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  fs::remove_all(abc.parent_path());
}

TEST(PluginTest, AMissingFileIsBadInput) {
  EXPECT_THROW(load_plugin("/nonexistent/libnothing.so", probe_settings()), InputError);
}

TEST(PluginTest, AnUnloadableLibraryIsAStrategyThatFails) {
  const fs::path garbage = write_temp("libgarbage-plugin.so.1", "not an ELF file\n");
  const std::string name = "garbage-plugin";
  const StrategyEntry& entry = load_plugin(garbage, probe_settings());
  EXPECT_EQ(entry.name, name);
  EXPECT_EQ(entry.role, "plugin");
  EXPECT_EQ(find_strategy(name), &entry);
  ASSERT_NE(strategy_library(entry), nullptr);
  EXPECT_EQ(strategy_library(entry)->path, fs::absolute(garbage).string());
  EXPECT_EQ(strategy_library(entry)->sha256, file_sha256(garbage));
  EXPECT_TRUE(entry.probe().available);  // its measurements are failed records, not absent
  ASSERT_TRUE(plugin_problem(entry));
  EXPECT_NE(plugin_problem(entry)->find("fails to load: "), std::string::npos);
  try {
    entry.create({});
    FAIL() << "create() of an unloadable plugin returned";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("fails to load: "), std::string::npos) << e.what();
  }
  // The same file again: its name is taken now.
  EXPECT_THROW(load_plugin(garbage, probe_settings()), InputError);
  fs::remove_all(garbage.parent_path());
}

// Whatever bytes a plugin hands back become one line of valid UTF-8.
TEST(PluginTest, PluginTextIsValidPrintableUtf8) {
  EXPECT_EQ(plugin_text("plain text"), "plain text");
  EXPECT_EQ(plugin_text("two\nlines\tand\r\x1b[2J"), "two\\nlines\\tand\\r\\x1b[2J");
  // Valid sequences of every length are kept.
  const std::string valid = "\xc3\xa9 \xe2\x82\xac \xf0\x9f\x98\x80";
  EXPECT_EQ(plugin_text(valid), valid);
  const std::string fffd = "\xef\xbf\xbd";
  // A stray continuation byte, an invalid lead byte, an overlong '/', a surrogate, a sequence cut
  // short, one past U+10FFFF: each a replacement character.
  EXPECT_EQ(plugin_text("a\x80"
                        "b"),
            "a" + fffd + "b");
  EXPECT_EQ(plugin_text("a\xff"
                        "b"),
            "a" + fffd + "b");
  EXPECT_EQ(plugin_text("\xc0\xaf"), fffd + fffd);
  EXPECT_EQ(plugin_text("\xed\xa0\x80"), fffd + fffd + fffd);
  EXPECT_EQ(plugin_text("x\xe2\x82"), "x" + fffd);
  EXPECT_EQ(plugin_text("\xf4\x90\x80\x80"), fffd + fffd + fffd + fffd);
  // C1 controls move a terminal too.
  EXPECT_EQ(plugin_text("\xc2\x85"), "\\u0085");
  EXPECT_EQ(plugin_text(std::string(100, 'a'), 10), std::string(10, 'a') + "...");
  EXPECT_EQ(plugin_text(std::string("nul\0byte", 8)), "nul\\x00byte");
}

TEST(PluginTest, ABuiltInNameCannotBeAdded) {
  EXPECT_EQ(strategy_library(*find_strategy("cpu-coxdeboor")), nullptr);
  StrategyEntry entry = *find_strategy("cpu-coxdeboor");
  EXPECT_THROW(add_strategy(entry, {"/x.so", "0"}), std::invalid_argument);
}

const StrategyEntry& echo() {
  static const StrategyEntry& entry = load_plugin(ECHO_PLUGIN, probe_settings());
  return entry;
}

double sum(const std::vector<double>& values) {
  double s = 0;
  for (double x : values) s += x;
  return s;
}

// What echo_plugin.cpp's digest() must come to, summed in its order from the Scene itself.
double expected_digest(const Surface& s) {
  std::vector<double> points, weights, homogeneous;
  for (std::size_t k = 0; k < s.control_points().size(); ++k) {
    const Point3& p = s.control_points()[k];
    const double w = s.control_weights()[k];
    points.insert(points.end(), p.begin(), p.end());
    weights.push_back(w);
    homogeneous.insert(homogeneous.end(), {p[0] * w, p[1] * w, p[2] * w, w});
  }
  double d = sum(s.is_tspline() ? s.tspline->knots_u : s.knots_u) +
             sum(s.is_tspline() ? s.tspline->knots_v : s.knots_v) + sum(points) + sum(weights) +
             sum(homogeneous);
  d += s.u_min() + s.u_max() + s.v_min() + s.v_max() + (s.trim ? s.trim->tolerance : 0.0);
  if (s.trim)
    for (const TrimLoop& loop : s.trim->loops)
      for (const TrimCurve& c : loop.curves) {
        std::vector<double> uv;
        for (const Point2& p : c.points) uv.insert(uv.end(), p.begin(), p.end());
        d += sum(c.knots) + sum(uv) + sum(c.weights);
      }
  return d;
}

TEST(PluginTest, CapabilitiesComeFromTheTable) {
  const Capabilities c = echo().capabilities();
  EXPECT_EQ(echo().name, "echo");
  EXPECT_EQ(echo().role, "plugin");
  EXPECT_TRUE(c.fp32 && c.fp64 && c.normals && c.rational && c.trims && c.tspline);
  EXPECT_TRUE(c.sampling.grid && c.sampling.span_grid && c.sampling.explicit_list);
  EXPECT_TRUE(c.updates_control_points);
  EXPECT_FALSE(c.tspline_only);
  EXPECT_EQ(c.max_degree, kMaxDegree);  // 0 in the table: the harness's limit
}

class EchoScenes : public ::testing::TestWithParam<std::tuple<std::string, Precision>> {};

TEST_P(EchoScenes, TheAdapterPassesTheSceneSamplesAndAlignedBuffers) {
  const auto& [name, precision] = GetParam();
  Scene scene = *make_builtin_scene(name);
  if (scene.surfaces.size() > 1) scene.surfaces[1].reversed = true;  // carried to the plugin
  EvalRequest request;
  request.sampling.grid_u = 5;
  request.sampling.grid_v = 3;
  request.precision = precision;
  request.normals = true;
  std::unique_ptr<Strategy> strategy = echo().create({});
  for (int frame = 0; frame < 2; ++frame) {
    // Frame 1: moved control points through update_control_points().
    if (frame == 0)
      strategy->prepare(scene, request);
    else
      strategy->update_control_points(scene = deformed_scene(scene, 1));
    strategy->evaluate();
    const EvalResult result = strategy->read_back();
    const std::vector<SurfaceSamples> samples = sample_parameters(scene, request.sampling);
    ASSERT_EQ(result.surfaces.size(), scene.surfaces.size());
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      const SurfaceResult& r = result.surfaces[i];
      ASSERT_EQ(r.positions.size(), samples[i].count());
      EXPECT_EQ(r.positions.precision(), precision);
      std::size_t trim_curves = 0, trim_points = 0;
      if (s.trim)
        for (const TrimLoop& loop : s.trim->loops) {
          trim_curves += loop.curves.size();
          for (const TrimCurve& c : loop.curves) trim_points += c.points.size();
        }
      const auto rounded = [&](double x) {
        return precision == Precision::f32 ? static_cast<double>(static_cast<float>(x)) : x;
      };
      const std::array<double, 3> expected_normal = {
          rounded(s.control_points().size() + 1e3 * s.count_u + 1e6 * s.count_v),
          rounded((s.is_tspline() ? 1 : 0) + 10.0 * s.degree_u + 100.0 * s.degree_v +
                  1e3 * s.reversed + 1e4 * s.is_rational()),
          rounded((s.trim ? s.trim->loops.size() : 0) + 1e2 * trim_curves + 1e4 * trim_points)};
      for (std::size_t k = 0; k < samples[i].count(); ++k) {
        const std::array<double, 3> expected = {
            rounded(samples[i].u_of(k)), rounded(samples[i].v_of(k)), rounded(expected_digest(s))};
        ASSERT_EQ(r.positions[k], expected) << name << " frame " << frame << " surface " << i;
        ASSERT_EQ(r.normals[k], expected_normal) << name << " surface " << i;
      }
      // The mask only for trimmed surfaces; 1: every array the plugin saw was 64-byte aligned.
      if (s.trim)
        EXPECT_EQ(r.inside, std::vector<std::uint8_t>(samples[i].count(), 1)) << name;
      else
        EXPECT_TRUE(r.inside.empty());
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, EchoScenes,
                         ::testing::Combine(::testing::Values("trimmed-plate", "duck",
                                                              "tspline-refined"),
                                            ::testing::Values(Precision::f32, Precision::f64)),
                         [](const auto& info) {
                           std::string name =
                               std::get<0>(info.param) +
                               (std::get<1>(info.param) == Precision::f32 ? "_f32" : "_f64");
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(PluginTest, ExplicitListsReachThePlugin) {
  const Scene scene = *make_builtin_scene("patch144");
  EvalRequest request;
  request.sampling.mode = SamplingMode::explicit_list;
  request.sampling.explicit_uv = {{{0.25, 0.5}, {1.0, 0.0}, {0.125, 0.875}}};
  request.precision = Precision::f64;
  std::unique_ptr<Strategy> strategy = echo().create({});
  strategy->prepare(scene, request);
  strategy->evaluate();
  const EvalResult result = strategy->read_back();
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(result.surfaces[0].positions[k][0], request.sampling.explicit_uv[0][k][0]);
    EXPECT_EQ(result.surfaces[0].positions[k][1], request.sampling.explicit_uv[0][k][1]);
  }
}

TEST(PluginTest, ErrorsBecomeRefusalsAndFailuresWithTheMessage) {
  const Scene scene = *make_builtin_scene("patch144");
  const auto message = [&](const std::string& where) -> std::string {
    try {
      auto strategy = echo().create({0, {{"fail", where}}});
      strategy->prepare(scene, {});
      strategy->evaluate();
    } catch (const RefusedError& e) {
      return std::string("refused: ") + e.what();
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message("create"),
            "plugin echo: create returned error 1: echo asked to fail in create");
  EXPECT_EQ(message("prepare"),
            "refused: plugin echo: prepare returned error 2: echo asked to fail in prepare");
  EXPECT_EQ(message("evaluate"),
            "plugin echo: evaluate returned error 1: echo asked to fail in evaluate");
}

}  // namespace
}  // namespace nurbs
