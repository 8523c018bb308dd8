// vk-compute's own cases beyond the shared accuracy suite (which runs every built-in scene, f32
// and f64, normals, all three samplings): many mixed faces in one dispatch, grids cut into many
// shared-memory tiles, degree 15, trims, update_control_points, device times, options. Positions
// are checked against the extended-precision reference (reference/reference_evaluator.h).
#include <gtest/gtest.h>

#include <cfloat>
#include <cstring>

#include "harness/metrics.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "tests/reference/random_nurbs.h"
#include "tests/strategies/gl_update_check.h"
#include "tests/strategies/trim_direct/strategy_trim_check.h"

namespace nurbs {
namespace {

const StrategyEntry& entry() {
  return *find_strategy("vk-compute");
}

#define SKIP_UNLESS_AVAILABLE()                                    \
  do {                                                             \
    const Availability a = entry().probe();                        \
    if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason; \
  } while (0)

Accuracy run_and_measure(const Scene& scene, const EvalRequest& request,
                         const StrategyOptions& options = {}) {
  auto s = entry().create(options);
  s->prepare(scene, request);
  s->evaluate();
  const EvalResult r = s->read_back();
  return measure_accuracy(
      scene, r,
      evaluate_reference(scene, sample_parameters(scene, request.sampling), request.normals));
}

// Knots mapped onto [0, 1]: random_knots' domains lie far from 0 (v near 33), where float
// parameter rounding alone costs hundreds of ulps in every f32 strategy (cpu-tensor and
// cpu-coxdeboor measured 424 on the wide net below).
Surface unit_domain(Surface s) {
  for (std::vector<double>* knots : {&s.knots_u, &s.knots_v}) {
    const double k0 = knots->front(), k1 = knots->back();
    for (double& k : *knots) k = k == k1 ? 1.0 : (k - k0) / (k1 - k0);
  }
  return s;
}

Sampling grid(int nu, int nv) {
  Sampling s;
  s.grid_u = nu;
  s.grid_v = nv;
  return s;
}

// Random faces of every degree pair and size, rational or not, clamped or not: one prepare, one
// dispatch per pass over all of them (the surface table), each face checked.
Scene mixed_faces() {
  test::Rng rng(29);
  Scene scene{"mixed", "random faces", {}};
  for (int k = 0; k < 40; ++k) {
    const int p = test::uniform_int(rng, 1, 15), q = test::uniform_int(rng, 1, 15);
    const int nu = p + 1 + test::uniform_int(rng, 0, 6), nv = q + 1 + test::uniform_int(rng, 0, 6);
    scene.surfaces.push_back(unit_domain(test::random_surface(
        rng, p, q, nu, nv, k % 3 == 0 ? test::Ends::unclamped : test::Ends::clamped, k % 2 == 0)));
  }
  return scene;
}

TEST(vk_compute, ManyMixedFacesInOneDispatchF32AndF64) {
  SKIP_UNLESS_AVAILABLE();
  const Scene scene = mixed_faces();
  for (Precision precision : {Precision::f32, Precision::f64})
    for (bool normals : {false, true}) {
      const Accuracy a = run_and_measure(scene, EvalRequest{grid(7, 5), precision, normals});
      EXPECT_EQ(a.non_finite, 0u);
      // the shared suite's budgets: 64 float ulps (GPU strategies), 64 double ulps
      EXPECT_LE(a.max_ulp, precision == Precision::f32 ? 64.0 : 64.0 * DBL_EPSILON / FLT_EPSILON)
          << to_string(precision) << (normals ? " normals" : "");
    }
}

// A scene whose surfaces share one degree pair gets an evaluation pass with the degrees as
// specialization constants; a scene of mixed degrees the pass that reads them from the table; one
// strategy going back and forth keeps both, and each is accurate.
TEST(vk_compute, OneDegreePairIsCompiledInMixedDegreesReadTheirs) {
  SKIP_UNLESS_AVAILABLE();
  test::Rng rng(30);
  Scene same{"same", "one degree pair", {}};
  for (int k = 0; k < 6; ++k)
    same.surfaces.push_back(
        unit_domain(test::random_surface(rng, 3, 2, 7, 5, test::Ends::clamped, k % 2 == 0)));
  const Scene mixed = mixed_faces();
  auto s = entry().create({});
  for (const Scene* scene : std::vector<const Scene*>{&same, &mixed, &same}) {
    const EvalRequest request{grid(9, 11), Precision::f32, true};
    s->prepare(*scene, request);
    EXPECT_EQ(s->device().details.at("vk_compute_degrees"),
              scene == &same ? "3x2 (constants)" : "per surface (mixed)");
    s->evaluate();
    const Accuracy a = measure_accuracy(
        *scene, s->read_back(),
        evaluate_reference(*scene, sample_parameters(*scene, request.sampling), true));
    EXPECT_EQ(a.non_finite, 0u) << scene->name;
    EXPECT_LE(a.max_ulp, 64.0) << scene->name;
  }
}

// A wide net (200 control points along v) on a grid wider than a work-group, with tiles capped at
// 24 curve points: many column runs per row, each with its own window of the net. f64 against the
// reference (a random net this wide has v-derivatives where f32 parameter rounding alone costs
// hundreds of ulps, in every f32 strategy); in f32 the capped tiling gives the uncapped one's
// floats exactly (the same sums in the same order, only cut differently).
TEST(vk_compute, GridCutIntoManyTilesMatchesTheReference) {
  SKIP_UNLESS_AVAILABLE();
  test::Rng rng(3);
  Scene scene{"wide",
              "a wide net",
              {unit_domain(test::random_surface(rng, 3, 5, 9, 200, test::Ends::clamped, true))}};
  StrategyOptions small;
  small.extra["vk-tile-points"] = "24";
  for (const StrategyOptions& options : {StrategyOptions{}, small}) {
    const Accuracy a =
        run_and_measure(scene, EvalRequest{grid(9, 300), Precision::f64, true}, options);
    EXPECT_EQ(a.non_finite, 0u);
    EXPECT_LE(a.max_ulp, 64.0 * DBL_EPSILON / FLT_EPSILON);
    ASSERT_TRUE(a.max_normal_angle_deg.has_value());
    EXPECT_LE(*a.max_normal_angle_deg, 1e-6);
  }
  std::vector<EvalResult> f32;
  for (const StrategyOptions& options : {StrategyOptions{}, small}) {
    auto s = entry().create(options);
    s->prepare(scene, EvalRequest{grid(9, 300), Precision::f32, true});
    s->evaluate();
    f32.push_back(s->read_back());
  }
  const std::size_t values = 9 * 300 * 3;
  for (auto member : {&SurfaceResult::positions, &SurfaceResult::normals}) {
    const PointArray &whole = f32[0].surfaces[0].*member, &cut = f32[1].surfaces[0].*member;
    ASSERT_EQ(whole.size(), cut.size());
    EXPECT_EQ(std::memcmp(whole.f32(), cut.f32(), values * sizeof(float)), 0);
  }
}

TEST(vk_compute, Degree15BothDirectionsExplicitAndSpanGrid) {
  SKIP_UNLESS_AVAILABLE();
  test::Rng rng(15);
  Scene scene{"d15",
              "degree 15",
              {unit_domain(test::random_surface(rng, 15, 15, 19, 18, test::Ends::clamped, true))}};
  Sampling span;
  span.mode = SamplingMode::span_grid;
  span.span_steps = 5;
  Sampling list;
  list.mode = SamplingMode::explicit_list;
  list.explicit_uv.emplace_back();
  for (int k = 0; k < 300; ++k)
    list.explicit_uv[0].push_back(
        {test::uniform_real(rng, scene.surfaces[0].u_min(), scene.surfaces[0].u_max()),
         test::uniform_real(rng, scene.surfaces[0].v_min(), scene.surfaces[0].v_max())});
  for (const Sampling& s : {span, list})
    for (Precision precision : {Precision::f32, Precision::f64}) {
      const Accuracy a = run_and_measure(scene, EvalRequest{s, precision, true});
      EXPECT_EQ(a.non_finite, 0u);
      EXPECT_LE(a.max_ulp, precision == Precision::f32 ? 64.0 : 64.0 * DBL_EPSILON / FLT_EPSILON)
          << s.label() << " " << to_string(precision);
    }
}

TEST(vk_compute_trim, TrimmedPlateExact) {
  test::expect_trimmed_plate_exact("vk-compute");
}
TEST(vk_compute_trim, HammerExact) {
  test::expect_hammer_exact("vk-compute");
}
TEST(vk_compute_trim, OptionsRefused) {
  test::expect_strategy_refuses_trim_options("vk-compute");
}

// Only the nets are sent again: the updated strategy gives, float for float, a fresh prepare's
// positions and masks (gl_update_check.h), on one surface, a trimmed span grid and many faces.
TEST(vk_compute, UpdateControlPointsEqualsAFreshPrepare) {
  SKIP_UNLESS_AVAILABLE();
  for (const GlUpdateCase& c : gl_update_cases(""))
    expect_update_equals_fresh_prepare(entry(), {}, *make_builtin_scene(c.scene), c.sampling, 64.0);
}

TEST(vk_compute, ReportsDeviceTimeOfTheEvaluatePhase) {
  SKIP_UNLESS_AVAILABLE();
  auto s = entry().create({});
  s->prepare(*make_builtin_scene("many-16"), EvalRequest{grid(32, 32), Precision::f32, false});
  s->evaluate();
  const DeviceTimes t = s->device_times();
  ASSERT_TRUE(t.evaluate_s.has_value()) << "lavapipe has timestamps";
  EXPECT_GT(*t.evaluate_s, 0.0);
}

TEST(vk_compute, TilePointsOptionRefusedWhenInvalid) {
  SKIP_UNLESS_AVAILABLE();
  for (const char* bad : {"15", "x", "32x", ""}) {
    StrategyOptions o;
    o.extra["vk-tile-points"] = bad;
    EXPECT_THROW(entry().create(o), std::invalid_argument) << bad;
  }
}

}  // namespace
}  // namespace nurbs
