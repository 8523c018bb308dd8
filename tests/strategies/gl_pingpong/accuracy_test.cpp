// gl-pingpong against the extended-precision reference on every built-in scene, on OSMesa and on
// EGL, unpacked and packed (000 §2.3), at grid and span-grid samples: within the 64
// float32 ulps of the scene's largest coordinate (see kBudgetUlp for the tightened gate). The
// generic strategy suite skips gl-pingpong (it asks for normals, which the paper's pipeline does
// not produce), so the per-scene accuracy lives here.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <stdexcept>
#include <tuple>

#include "harness/metrics.h"
#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/registry.h"
#include "tests/strategies/gl_update_check.h"

namespace nurbs {
namespace {

// The issue asks 64; tightened to 32 (the CPU evaluators' bound) since the measured worst over
// these scenes is 14.9 (clustered: float rounding of the parameter, as for cpu-coxdeboor) and
// under 5 elsewhere, identical on OSMesa and EGL, packed or not (results/gates.json).
constexpr double kBudgetUlp = 32.0;

const std::vector<std::string> kScenes = {
    "patch144",  "tan16",      "sphere",   "torus",    "degree-1", "degree-2", "degree-3",
    "degree-4",  "degree-5",   "degree-6", "degree-7", "degree-8", "degree-9", "creases",
    "clustered", "far-origin", "teapot",   "duck",     "many-16"};

struct Case {
  std::string platform;
  std::string strategy;
};

StrategyOptions options_for(const std::string& platform, const std::string& tile = "") {
  StrategyOptions o;
  o.extra["gl"] = platform;
  if (!tile.empty()) o.extra["tile"] = tile;
  return o;
}

EvalResult evaluate(const StrategyEntry& entry, const StrategyOptions& options, const Scene& scene,
                    const Sampling& sampling) {
  auto strategy = entry.create(options);
  strategy->prepare(scene, EvalRequest{sampling, Precision::f32, false});
  strategy->evaluate();
  return strategy->read_back();
}

std::vector<Sampling> samplings() {
  Sampling grid;
  grid.grid_u = 33;
  grid.grid_v = 29;
  Sampling span;
  span.mode = SamplingMode::span_grid;
  span.span_steps = 3;
  return {grid, span};
}

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.platform << "/" << c.strategy;
}

class GlPingPongAccuracy : public ::testing::TestWithParam<Case> {};

TEST_P(GlPingPongAccuracy, WithinBudgetOnEveryBuiltinScene) {
  const auto platform = gl::parse_platform(GetParam().platform);
  const Availability a = gl::Context::probe(*platform);
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  const StrategyEntry& entry = *find_strategy(GetParam().strategy);
  for (const std::string& name : kScenes) {
    const Scene scene = *make_builtin_scene(name);
    double worst = 0;
    for (const Sampling& sampling : samplings()) {
      const EvalResult result = evaluate(entry, options_for(GetParam().platform), scene, sampling);
      const Accuracy acc = measure_accuracy(
          scene, result, evaluate_reference(scene, sample_parameters(scene, sampling), false));
      EXPECT_EQ(acc.non_finite, 0u) << name;
      EXPECT_LE(acc.max_ulp, kBudgetUlp)
          << entry.name << " (" << GetParam().platform << ") on " << name << " ("
          << sampling.label() << "): worst at surface " << acc.worst_surface << " u=" << acc.worst_u
          << " v=" << acc.worst_v;
      worst = std::max(worst, acc.max_ulp);
    }
    std::cout << entry.name << " " << GetParam().platform << " " << name << ": max_ulp " << worst
              << "\n";
  }
}

// Grids beyond one texture are tiled, never truncated: with 7-texel tiles (chunks of 7
// parameters, tiles of 7x7 samples, partial ones at the edges) every point is bit-identical to
// the untiled run, since each sample's arithmetic does not depend on its tile.
TEST_P(GlPingPongAccuracy, TiledGridEqualsUntiled) {
  const auto platform = gl::parse_platform(GetParam().platform);
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  const StrategyEntry& entry = *find_strategy(GetParam().strategy);
  const Scene scene = *make_builtin_scene("many-16");
  Sampling grid;
  grid.grid_u = 30;
  grid.grid_v = 17;
  const EvalResult whole = evaluate(entry, options_for(GetParam().platform), scene, grid);
  const EvalResult tiled = evaluate(entry, options_for(GetParam().platform, "7"), scene, grid);
  ASSERT_EQ(whole.surfaces.size(), tiled.surfaces.size());
  for (std::size_t i = 0; i < whole.surfaces.size(); ++i) {
    const PointArray &w = whole.surfaces[i].positions, &t = tiled.surfaces[i].positions;
    ASSERT_EQ(t.size(), 30u * 17u);
    for (std::size_t k = 0; k < w.size(); ++k)
      ASSERT_EQ(w[k], t[k]) << "surface " << i << " sample " << k;
  }
  auto strategy = entry.create(options_for(GetParam().platform, "7"));
  strategy->prepare(scene, EvalRequest{grid, Precision::f32, false});
  EXPECT_EQ(strategy->device().details.at("tiles"), std::to_string(16 * 5 * 3));
}

TEST_P(GlPingPongAccuracy, RecordsDeviceTimesPassesAndBytes) {
  const auto platform = gl::parse_platform(GetParam().platform);
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  const StrategyEntry& entry = *find_strategy(GetParam().strategy);
  const Scene scene = *make_builtin_scene("patch144");  // bicubic, 12x12
  Sampling grid;
  grid.grid_u = 16;
  grid.grid_v = 16;
  auto strategy = entry.create(options_for(GetParam().platform));
  strategy->prepare(scene, EvalRequest{grid, Precision::f32, false});
  strategy->evaluate();
  ASSERT_TRUE(strategy->device_times().evaluate_s.has_value());
  EXPECT_GT(*strategy->device_times().evaluate_s, 0.0);
  const DeviceInfo d = strategy->device();
  // 3 + 3 basis passes (k-1 per direction), 16 accumulation passes (000 §3.1), 1 divide.
  EXPECT_EQ(d.details.at("passes"), "23");
  EXPECT_FALSE(d.details.at("gl_renderer").empty());
  EXPECT_FALSE(d.details.at("gl_version").empty());
  // control points 144 x 16 bytes; per direction: knot array 16 x 9 texels, order-1 16 x 5
  // texels (1 float each unpacked, 4 floats per 4 parameters packed: the same bytes), span
  // indices 16 x 4 bytes.
  const std::size_t per_direction = 16 * 9 * 4 + 16 * 5 * 4 + 16 * 4;
  EXPECT_EQ(d.details.at("bytes_uploaded"), std::to_string(144 * 16 + 2 * per_direction));
}

// The record's passes are the draws evaluate() issued (gl::DrawCounts), checked here against 000
// §3.1 counted per surface by hand: the recurrence raises the order-1 basis to order k in k-1
// ping-pong passes, in each direction and for each chunk of that direction's parameters (a tiled
// grid raises every chunk); every tile then sums its k_u x k_v basis products one pass each and
// divides by w in one more. A second evaluate() reports its own passes, not a running total.
TEST_P(GlPingPongAccuracy, PassesAreTheDrawsOf000) {
  const auto platform = gl::parse_platform(GetParam().platform);
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  const StrategyEntry& entry = *find_strategy(GetParam().strategy);
  struct PassCase {
    std::string scene;
    int grid_u, grid_v;
    int tile;  // 0: the whole grid in one texture
  };
  for (const PassCase& c : {PassCase{"degree-1", 16, 16, 0}, PassCase{"degree-7", 9, 12, 0},
                            PassCase{"duck", 33, 29, 0}, PassCase{"many-16", 30, 17, 7},
                            PassCase{"torus", 20, 11, 8}}) {
    SCOPED_TRACE(c.scene);
    const Scene scene = *make_builtin_scene(c.scene);
    std::size_t basis = 0, accumulate_and_divide = 0;
    for (const Surface& s : scene.surfaces) {
      const int chunks_u = c.tile ? (c.grid_u + c.tile - 1) / c.tile : 1;
      const int chunks_v = c.tile ? (c.grid_v + c.tile - 1) / c.tile : 1;
      const int order_u = s.degree_u + 1, order_v = s.degree_v + 1;
      basis += static_cast<std::size_t>(chunks_u * (order_u - 1) + chunks_v * (order_v - 1));
      accumulate_and_divide += static_cast<std::size_t>(chunks_u * chunks_v) *
                               static_cast<std::size_t>(order_u * order_v + 1);
    }
    Sampling grid;
    grid.grid_u = c.grid_u;
    grid.grid_v = c.grid_v;
    auto strategy =
        entry.create(options_for(GetParam().platform, c.tile ? std::to_string(c.tile) : ""));
    strategy->prepare(scene, EvalRequest{grid, Precision::f32, false});
    EXPECT_EQ(strategy->device().details.at("passes"), "0");  // nothing drawn yet
    for (int run = 0; run < 2; ++run) {
      strategy->evaluate();
      const DeviceInfo d = strategy->device();
      EXPECT_EQ(d.details.at("passes_basis"), std::to_string(basis)) << "evaluate " << run;
      EXPECT_EQ(d.details.at("passes"), std::to_string(basis + accumulate_and_divide))
          << "evaluate " << run;
    }
  }
}

// 000 §5's deforming surfaces: update_control_points rewrites only the control-point textures, so
// an updated strategy equals a freshly prepared one bit for bit -- one surface, a trimmed one (the
// trim textures stay from prepare), many surfaces over 7-texel tiles -- and sends only the points.
TEST_P(GlPingPongAccuracy, UpdateControlPointsEqualsAFreshPrepare) {
  const auto platform = gl::parse_platform(GetParam().platform);
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  const StrategyEntry& entry = *find_strategy(GetParam().strategy);
  EXPECT_TRUE(entry.capabilities().updates_control_points);
  for (const GlUpdateCase& c : gl_update_cases("7")) {
    SCOPED_TRACE(c.scene);
    const Scene scene = *make_builtin_scene(c.scene);
    const DeviceInfo d = expect_update_equals_fresh_prepare(
        entry, options_for(GetParam().platform, c.tile), scene, c.sampling, kBudgetUlp);
    std::size_t points = 0;
    for (const Surface& s : scene.surfaces) points += s.points.size();
    EXPECT_EQ(d.details.at("bytes_updated"), std::to_string(points * 4 * sizeof(float)));
  }
  auto strategy = entry.create(options_for(GetParam().platform));
  strategy->prepare(*make_builtin_scene("patch144"),
                    EvalRequest{gl_update_cases("").front().sampling, Precision::f32, false});
  EXPECT_THROW(strategy->update_control_points(*make_builtin_scene("degree-3")),
               std::invalid_argument);
  EXPECT_THROW(strategy->update_control_points(*make_builtin_scene("many-2")),
               std::invalid_argument);
}

// The deforming benchmark times update_control_points as "frame_update" and scores the last
// frame, trims included.
TEST_P(GlPingPongAccuracy, DeformingRunUpdatesAndLandsOnTheLastFrame) {
  const auto platform = gl::parse_platform(GetParam().platform);
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  Sampling grid;
  grid.grid_u = 33;
  grid.grid_v = 29;
  for (const char* name : {"patch144", "trimmed-plate"}) {
    const Record r =
        measure_deforming(*find_strategy(GetParam().strategy), options_for(GetParam().platform),
                          *make_builtin_scene(name), EvalRequest{grid, Precision::f32, false}, 3,
                          ReferencePrecision::long_double);
    ASSERT_EQ(r.status, Status::ok) << name << ": " << r.reason;
    ASSERT_TRUE(r.accuracy.has_value());
    EXPECT_LE(r.accuracy->max_ulp, kBudgetUlp) << name;
    EXPECT_TRUE(r.extra_phases.count("frame_update")) << name;
    EXPECT_FALSE(r.extra_phases.count("frame_prepare")) << name;
  }
}

INSTANTIATE_TEST_SUITE_P(Platforms, GlPingPongAccuracy,
                         ::testing::Values(Case{"osmesa", "gl-pingpong"},
                                           Case{"osmesa", "gl-pingpong-packed"},
                                           Case{"egl", "gl-pingpong"},
                                           Case{"egl", "gl-pingpong-packed"}),
                         [](const auto& info) {
                           std::string s = info.param.platform + "_" + info.param.strategy;
                           std::replace(s.begin(), s.end(), '-', '_');
                           return s;
                         });

}  // namespace
}  // namespace nurbs
