// glsl-deboor on the GL plumbing: OSMesa and EGL give the same points, paging the atlas (a small
// tile option) changes nothing bit-for-bit, the record carries device times and quad counts.
// The per-scene accuracy of the default (EGL) path is the generic strategy_accuracy_test.
#include <gtest/gtest.h>

#include "harness/metrics.h"
#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/glsl_deboor/span_runs.h"
#include "strategies/registry.h"

namespace nurbs {
namespace {

StrategyOptions options_for(const std::string& platform, const std::string& tile = "") {
  StrategyOptions o;
  o.extra["gl"] = platform;
  if (!tile.empty()) o.extra["tile"] = tile;
  return o;
}

EvalResult evaluate(const StrategyOptions& options, const Scene& scene, const Sampling& sampling) {
  auto strategy = find_strategy("glsl-deboor")->create(options);
  strategy->prepare(scene, EvalRequest{sampling, Precision::f32, false});
  strategy->evaluate();
  return strategy->read_back();
}

void expect_identical(const EvalResult& a, const EvalResult& b) {
  ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
  for (std::size_t i = 0; i < a.surfaces.size(); ++i) {
    const PointArray &x = a.surfaces[i].positions, &y = b.surfaces[i].positions;
    ASSERT_EQ(x.size(), y.size());
    for (std::size_t k = 0; k < x.size(); ++k) ASSERT_EQ(x[k], y[k]) << "surface " << i << " " << k;
  }
}

class GlslDeBoorGl : public ::testing::TestWithParam<std::string> {};

TEST_P(GlslDeBoorGl, WithinBudgetOnCurvedHighDegreeAndClusteredScenes) {
  const auto platform = gl::parse_platform(GetParam());
  const Availability a = gl::Context::probe(*platform);
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  for (const char* name : {"sphere", "degree-9", "clustered"}) {
    const Scene scene = *make_builtin_scene(name);
    Sampling span;
    span.mode = SamplingMode::span_grid;
    span.span_steps = 3;
    for (const Sampling& sampling : {Sampling{}, span}) {
      const EvalResult result = evaluate(options_for(GetParam()), scene, sampling);
      const Accuracy acc = measure_accuracy(
          scene, result, evaluate_reference(scene, sample_parameters(scene, sampling), false));
      EXPECT_EQ(acc.non_finite, 0u) << name;
      EXPECT_LE(acc.max_ulp, 16.0) << name << " " << sampling.label();
    }
  }
}

// Many surfaces, pages of at most 40 rows: every surface lands in some page, bit-identical to one
// page (each texel's arithmetic does not depend on where its surface sits).
TEST_P(GlslDeBoorGl, PagedAtlasEqualsOnePage) {
  const auto platform = gl::parse_platform(GetParam());
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  const Scene scene = *make_builtin_scene("many-16");
  Sampling grid;
  grid.grid_u = 30;
  grid.grid_v = 17;
  expect_identical(evaluate(options_for(GetParam()), scene, grid),
                   evaluate(options_for(GetParam(), "40"), scene, grid));
  auto strategy = find_strategy("glsl-deboor")->create(options_for(GetParam(), "40"));
  strategy->prepare(scene, EvalRequest{grid, Precision::f32, false});
  EXPECT_EQ(strategy->device().details.at("pages"), "8");  // 17 + 17 rows fit in 40
}

TEST_P(GlslDeBoorGl, RefusesASurfaceLargerThanATile) {
  const auto platform = gl::parse_platform(GetParam());
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  auto strategy = find_strategy("glsl-deboor")->create(options_for(GetParam(), "20"));
  Sampling grid;
  grid.grid_u = 21;
  EXPECT_THROW(
      strategy->prepare(*make_builtin_scene("patch144"), EvalRequest{grid, Precision::f32, false}),
      RefusedError);
}

TEST_P(GlslDeBoorGl, RecordsDeviceTimesAndOneQuadPerSpanWithSamples) {
  const auto platform = gl::parse_platform(GetParam());
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  const Scene scene = *make_builtin_scene("patch144");  // bicubic, 12x12, 9 spans each way
  Sampling grid;
  grid.grid_u = 16;
  grid.grid_v = 16;
  auto strategy = find_strategy("glsl-deboor")->create(options_for(GetParam()));
  strategy->prepare(scene, EvalRequest{grid, Precision::f32, false});
  strategy->evaluate();
  ASSERT_TRUE(strategy->device_times().evaluate_s.has_value());
  EXPECT_GT(*strategy->device_times().evaluate_s, 0.0);
  const DeviceInfo d = strategy->device();
  EXPECT_EQ(d.details.at("passes"), "2");
  // Samples a/15: every u span holds one (9 quads); v span [0.15, 0.2) holds none (2/15 < 0.15,
  // 3/15 = 0.2 belongs to the next span), so 8 quads in v: a quad only where samples are.
  EXPECT_EQ(d.details.at("quads"), "17");
  // 12x12 texels of control points, 16 + 16 float parameters.
  EXPECT_EQ(d.details.at("bytes_uploaded"), std::to_string(144 * 16 + 2 * 16 * 4));
}

// 002 §4.2 in `run`: the record carries both render phases beside evaluate.
TEST_P(GlslDeBoorGl, RunRecordsBothRenderPhases) {
  const auto platform = gl::parse_platform(GetParam());
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  const Scene scene = *make_builtin_scene("sphere");
  Sampling grid;
  grid.grid_u = 32;
  grid.grid_v = 32;
  ReferenceCache references;
  const Record r = measure(*find_strategy("glsl-deboor"), options_for(GetParam()), scene,
                           EvalRequest{grid, Precision::f32, false}, 2, references);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  for (const char* phase : {"render", "render_via_read_back"}) {
    ASSERT_EQ(r.extra_phases.count(phase), 1u) << phase;
    EXPECT_GT(r.extra_phases.at(phase).min_s, 0.0) << phase;
  }
}

TEST(GlslDeBoorGl, OsmesaAndEglAgree) {
  if (!gl::Context::probe(gl::Platform::osmesa).available ||
      !gl::Context::probe(gl::Platform::egl).available)
    GTEST_SKIP();
  const Scene scene = *make_builtin_scene("torus");
  expect_identical(evaluate(options_for("osmesa"), scene, Sampling{}),
                   evaluate(options_for("egl"), scene, Sampling{}));
}

INSTANTIATE_TEST_SUITE_P(Platforms, GlslDeBoorGl, ::testing::Values("osmesa", "egl"));

}  // namespace
}  // namespace nurbs
