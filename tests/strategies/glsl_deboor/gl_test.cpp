// glsl-deboor on the GL plumbing: OSMesa and EGL give the same points, paging the atlas (a small
// tile option) changes nothing bit-for-bit, the record carries device times and the quads and
// passes it drew.
// The per-scene accuracy of the default (EGL) path is the generic strategy_accuracy_test.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>
#include <tuple>

#include "harness/metrics.h"
#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/glsl_deboor/span_runs.h"
#include "strategies/registry.h"
#include "tests/strategies/gl_update_check.h"

namespace nurbs {
namespace {

// Float32 ulps of the scene's largest coordinate (harness/metrics.h).
constexpr double kBudgetUlp = 16.0;

StrategyOptions options_for(const std::string& platform, const std::string& tile = "",
                            const std::string& draw = "") {
  StrategyOptions o;
  o.extra["gl"] = platform;
  if (!tile.empty()) o.extra["tile"] = tile;
  if (!draw.empty()) o.extra["deboor-draw"] = draw;
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
      EXPECT_LE(acc.max_ulp, kBudgetUlp) << name << " " << sampling.label();
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
  grid.grid_u = 17;  // the output atlas stacks u samples (rows of v runs): 17 rows a surface
  grid.grid_v = 30;
  expect_identical(evaluate(options_for(GetParam()), scene, grid),
                   evaluate(options_for(GetParam(), "40"), scene, grid));
  auto strategy = find_strategy("glsl-deboor")->create(options_for(GetParam(), "40"));
  strategy->prepare(scene, EvalRequest{grid, Precision::f32, false});
  EXPECT_EQ(strategy->device().details.at("pages"), "8");  // 17 + 17 output rows fit in 40
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

// The knot intervals [t_i, t_i+1) of the domain that are not empty and hold a parameter, read off
// the knot vector directly (not by span search, as bin_into_spans does): the parameter at the end
// of the domain belongs to the last non-empty interval.
std::size_t spans_holding_samples(const std::vector<double>& knots, int degree, int count,
                                  const std::vector<double>& parameters) {
  int last = count - 1;
  while (knots[static_cast<std::size_t>(last)] == knots[static_cast<std::size_t>(last) + 1]) --last;
  std::size_t spans = 0;
  for (int i = degree; i < count; ++i) {
    const double lo = knots[static_cast<std::size_t>(i)],
                 hi = knots[static_cast<std::size_t>(i) + 1];
    if (lo == hi) continue;
    const bool holds = std::any_of(parameters.begin(), parameters.end(), [&](double p) {
      return (lo <= p && p < hi) || (i == last && p == hi);
    });
    spans += holds ? 1 : 0;
  }
  return spans;
}

// The record's passes and quads are the draws evaluate() issued (gl::DrawCounts), checked against
// 002 §3.3 derived from the scene: a quad per non-empty knot span holding samples, per surface,
// in u (pass 1) and in v (pass 2); one pass per direction and atlas page, each drawing all its
// quads into one target. Creases (repeated knots: empty spans) and clustered knots (spans without
// samples) skip quads; the 40-row tile pages many-16. A second evaluate() reports its own draws.
TEST_P(GlslDeBoorGl, PassesAndQuadsAreTheDrawsOf002) {
  const auto platform = gl::parse_platform(GetParam());
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  Sampling span;
  span.mode = SamplingMode::span_grid;
  span.span_steps = 2;
  Sampling grid;
  grid.grid_u = 17;  // the output atlas stacks u samples (rows of v runs): 17 rows a surface
  grid.grid_v = 30;
  struct QuadCase {
    std::string scene;
    Sampling sampling;
    std::string tile;
    std::size_t pages;
  };
  for (const QuadCase& c : {QuadCase{"creases", grid, "", 1}, QuadCase{"clustered", grid, "", 1},
                            QuadCase{"clustered", span, "", 1}, QuadCase{"duck", grid, "", 1},
                            QuadCase{"many-16", grid, "40", 8}}) {
    SCOPED_TRACE(c.scene + " " + c.sampling.label());
    const Scene scene = *make_builtin_scene(c.scene);
    const std::vector<SurfaceSamples> samples = sample_parameters(scene, c.sampling);
    std::size_t quads = 0;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      quads += spans_holding_samples(s.knots_u, s.degree_u, s.count_u, samples[i].u) +
               spans_holding_samples(s.knots_v, s.degree_v, s.count_v, samples[i].v);
    }
    auto strategy = find_strategy("glsl-deboor")->create(options_for(GetParam(), c.tile));
    strategy->prepare(scene, EvalRequest{c.sampling, Precision::f32, false});
    EXPECT_EQ(strategy->device().details.at("quads"), "0");  // nothing drawn yet
    for (int run = 0; run < 2; ++run) {
      strategy->evaluate();
      const DeviceInfo d = strategy->device();
      EXPECT_EQ(d.details.at("pages"), std::to_string(c.pages));
      EXPECT_EQ(d.details.at("passes"), std::to_string(2 * c.pages)) << "evaluate " << run;
      EXPECT_EQ(d.details.at("quads"), std::to_string(quads)) << "evaluate " << run;
    }
  }
}

// deboor-draw=instanced moves the per-span values from uniforms into instance tables and draws
// each pass and degree once: every texel is computed from the same values, so the points equal
// the per-span form's bit for bit -- rational, degree 9, clustered and creased knots, span-grid
// sampling, many surfaces over 8 pages, surfaces of three degrees in one page -- with the same
// quads, as one draw per pass and degree.
TEST_P(GlslDeBoorGl, InstancedDrawEqualsPerSpanInOneDrawPerPass) {
  const auto platform = gl::parse_platform(GetParam());
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  Sampling grid;
  grid.grid_u = 17;  // the output atlas stacks u samples (rows of v runs): 17 rows a surface
  grid.grid_v = 30;
  Sampling span;
  span.mode = SamplingMode::span_grid;
  span.span_steps = 3;
  for (const auto& [name, sampling, tile] :
       {std::tuple{"sphere", grid, ""}, std::tuple{"degree-9", span, ""},
        std::tuple{"clustered", span, ""}, std::tuple{"creases", grid, ""},
        std::tuple{"tan64", grid, ""}, std::tuple{"many-16", grid, "40"},
        std::tuple{"mixed", grid, ""}}) {
    SCOPED_TRACE(name);
    Scene scene;
    std::set<int> degrees_u, degrees_v;  // of the one page: a draw per pass and degree
    if (std::string(name) == "mixed") {
      for (const char* part : {"sphere", "patch144", "degree-9"}) {
        const Scene one = *make_builtin_scene(part);
        scene.surfaces.insert(scene.surfaces.end(), one.surfaces.begin(), one.surfaces.end());
      }
    } else {
      scene = *make_builtin_scene(name);
    }
    for (const Surface& s : scene.surfaces) {
      degrees_u.insert(s.degree_u);
      degrees_v.insert(s.degree_v);
    }
    auto per_span = find_strategy("glsl-deboor")->create(options_for(GetParam(), tile));
    auto instanced =
        find_strategy("glsl-deboor")->create(options_for(GetParam(), tile, "instanced"));
    const EvalRequest request{sampling, Precision::f32, false};
    per_span->prepare(scene, request);
    instanced->prepare(scene, request);
    per_span->evaluate();
    instanced->evaluate();
    expect_identical(per_span->read_back(), instanced->read_back());
    const DeviceInfo a = per_span->device(), b = instanced->device();
    EXPECT_EQ(a.details.at("draw"), "per-span");
    EXPECT_EQ(b.details.at("draw"), "instanced");
    EXPECT_EQ(a.details.at("draws"), a.details.at("quads"));
    EXPECT_EQ(b.details.at("quads"), a.details.at("quads"));
    EXPECT_EQ(b.details.at("passes"), a.details.at("passes"));
    if (b.details.at("pages") == "1")
      EXPECT_EQ(b.details.at("draws"), std::to_string(degrees_u.size() + degrees_v.size()));
    else  // many-16: bicubic only
      EXPECT_EQ(b.details.at("draws"), b.details.at("passes"));
    EXPECT_GT(std::stoul(a.details.at("draws")), std::stoul(a.details.at("passes")));
  }
  EXPECT_THROW(find_strategy("glsl-deboor")->create(options_for(GetParam(), "", "batched")),
               std::invalid_argument);
}

// 000 §5's deforming surfaces: update_control_points rewrites only the pages' control textures, so
// an updated strategy equals a freshly prepared one bit for bit -- one surface, a trimmed one (the
// trim textures stay from prepare), many surfaces paged over 40-row tiles.
TEST_P(GlslDeBoorGl, UpdateControlPointsEqualsAFreshPrepare) {
  const auto platform = gl::parse_platform(GetParam());
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  const StrategyEntry& entry = *find_strategy("glsl-deboor");
  EXPECT_TRUE(entry.capabilities().updates_control_points);
  for (const GlUpdateCase& c : gl_update_cases("40")) {
    SCOPED_TRACE(c.scene);
    const DeviceInfo d =
        expect_update_equals_fresh_prepare(entry, options_for(GetParam(), c.tile),
                                           *make_builtin_scene(c.scene), c.sampling, kBudgetUlp);
    EXPECT_EQ(d.details.count("bytes_updated"), 1u);
  }
  // patch144 alone: its page's control texture is exactly its 12 x 12 net.
  auto strategy = entry.create(options_for(GetParam()));
  strategy->prepare(*make_builtin_scene("patch144"),
                    EvalRequest{gl_update_cases("").front().sampling, Precision::f32, false});
  strategy->update_control_points(deformed_scene(*make_builtin_scene("patch144"), 1));
  EXPECT_EQ(strategy->device().details.at("bytes_updated"), std::to_string(144 * 16));
  EXPECT_THROW(strategy->update_control_points(*make_builtin_scene("degree-3")),
               std::invalid_argument);
  EXPECT_THROW(strategy->update_control_points(*make_builtin_scene("many-2")),
               std::invalid_argument);
}

// The deforming benchmark times update_control_points as "frame_update" and scores the last
// frame, trims included.
TEST_P(GlslDeBoorGl, DeformingRunUpdatesAndLandsOnTheLastFrame) {
  const auto platform = gl::parse_platform(GetParam());
  if (!gl::Context::probe(*platform).available) GTEST_SKIP();
  Sampling grid;
  grid.grid_u = 33;
  grid.grid_v = 29;
  for (const char* name : {"patch144", "trimmed-plate"}) {
    const Record r = measure_deforming(
        *find_strategy("glsl-deboor"), options_for(GetParam()), *make_builtin_scene(name),
        EvalRequest{grid, Precision::f32, false}, 3, ReferencePrecision::long_double);
    ASSERT_EQ(r.status, Status::ok) << name << ": " << r.reason;
    ASSERT_TRUE(r.accuracy.has_value());
    EXPECT_LE(r.accuracy->max_ulp, kBudgetUlp) << name;
    EXPECT_TRUE(r.extra_phases.count("frame_update")) << name;
    EXPECT_FALSE(r.extra_phases.count("frame_prepare")) << name;
  }
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
