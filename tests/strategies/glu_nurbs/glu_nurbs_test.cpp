// glu-nurbs: where GLU samples and what it returns, checked against values computed here.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "harness/runner.h"
#include "reference/trim_classify.h"
#include "scenes/builtin_scenes.h"
#include "scenes/trimmed_plate.h"
#include "strategies/registry.h"
#include "tests/scenes/high_degree_trim.h"
#include "tests/scenes/trimmed_plate_closed_form.h"

namespace nurbs {
namespace {

const StrategyEntry& glu() {
  return *find_strategy("glu-nurbs");
}

// One bicubic Bezier patch over [0, 2] x [0, 1] (one span each way): GLU_DOMAIN_DISTANCE with
// the step of an NU x NV grid samples it exactly on that grid.
Scene bezier_scene(bool rational) {
  Surface s;
  s.name = "bezier";
  s.degree_u = s.degree_v = 3;
  s.count_u = s.count_v = 4;
  s.knots_u = {0, 0, 0, 0, 2, 2, 2, 2};
  s.knots_v = {0, 0, 0, 0, 1, 1, 1, 1};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      s.points.push_back({1.0 * i, 1.0 * j, 0.25 * ((i * j) % 3)});
      s.weights.push_back(rational ? 1.0 + 0.25 * ((i + j) % 2) : 1.0);
    }
  return Scene{"bezier", "", {s}};
}

EvalResult run(const Scene& scene, int nu, int nv) {
  Sampling grid;
  grid.grid_u = nu;
  grid.grid_v = nv;
  auto strategy = glu().create(StrategyOptions{});
  strategy->prepare(scene, EvalRequest{grid, Precision::f32, false});
  strategy->evaluate();
  strategy->evaluate();  // a second evaluate replaces, never appends to, the first
  return strategy->read_back();
}

TEST(GluNurbs, SamplesOneBezierPatchOnTheRequestedGrid) {
  if (!glu().probe().available) GTEST_SKIP() << glu().probe().reason;
  for (bool rational : {false, true}) {
    const Scene scene = bezier_scene(rational);
    const EvalResult result = run(scene, 9, 5);
    ASSERT_EQ(result.surfaces.size(), 1u);
    const SurfaceResult& r = result.surfaces[0];
    EXPECT_FALSE(r.samples.tensor);
    ASSERT_EQ(r.positions.size(), 45u);  // each of the 9 x 5 vertices once
    std::set<std::pair<double, double>> expected, got;
    for (int a = 0; a < 9; ++a)
      for (int b = 0; b < 5; ++b) expected.insert({2.0 * a / 8, 1.0 * b / 4});
    for (std::size_t k = 0; k < r.samples.count(); ++k)
      got.insert({r.samples.u_of(k), r.samples.v_of(k)});
    EXPECT_EQ(got, expected);
    const Accuracy acc =
        measure_accuracy(scene, result, evaluate_reference(scene, result_samples(result), false));
    EXPECT_LE(acc.max_ulp, 4.0) << (rational ? "rational" : "polynomial");
  }
}

TEST(GluNurbs, SamplesLieInTheDomainAndEveryKnotIsSampled) {
  if (!glu().probe().available) GTEST_SKIP() << glu().probe().reason;
  const Scene scene = *make_builtin_scene("patch144");
  const Surface& s = scene.surfaces[0];
  const EvalResult result = run(scene, 64, 64);
  const SurfaceSamples& samples = result.surfaces[0].samples;
  std::set<float> us;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    EXPECT_GE(samples.u_of(k), s.u_min());
    EXPECT_LE(samples.u_of(k), s.u_max());
    EXPECT_GE(samples.v_of(k), s.v_min());
    EXPECT_LE(samples.v_of(k), s.v_max());
    us.insert(static_cast<float>(samples.u_of(k)));
  }
  // GLU evaluates Bezier patch by Bezier patch: the knots are sample lines.
  for (int i = s.degree_u; i <= s.count_u; ++i)
    EXPECT_TRUE(us.count(static_cast<float>(s.knots_u[i]))) << "knot " << s.knots_u[i];
  // About the requested density: per Bezier patch GLU takes step * length intervals, rounded.
  EXPECT_GT(samples.count(), 64u * 64u * 8 / 10);
  EXPECT_LT(samples.count(), 64u * 64u * 12 / 10);
}

TEST(GluNurbs, RefusesWhatItCannotDo) {
  const Capabilities caps = glu().capabilities();
  EXPECT_TRUE(caps.chooses_own_samples);
  EXPECT_FALSE(caps.fp64);
  EXPECT_FALSE(caps.normals);
  EXPECT_TRUE(caps.sampling.grid);
  EXPECT_FALSE(caps.sampling.span_grid);
  EXPECT_FALSE(caps.sampling.explicit_list);
  EXPECT_EQ(glu().role, "baseline");
  if (!glu().probe().available) GTEST_SKIP() << glu().probe().reason;
  const Scene scene = bezier_scene(false);
  Sampling span;
  span.mode = SamplingMode::span_grid;
  auto strategy = glu().create(StrategyOptions{});
  EXPECT_THROW(strategy->prepare(scene, EvalRequest{Sampling{}, Precision::f64, false}),
               RefusedError);
  EXPECT_THROW(strategy->prepare(scene, EvalRequest{span, Precision::f32, false}), RefusedError);
  EXPECT_THROW(strategy->prepare(scene, EvalRequest{Sampling{}, Precision::f32, true}),
               RefusedError);
}

// The trimmed plate's loops with every curve run backwards (outer clockwise, hole
// counter-clockwise): the same face under the scene's even-odd rule.
Scene reversed_plate() {
  Scene scene = trimmed_plate_scene();
  for (TrimLoop& loop : scene.surfaces[0].trim->loops) {
    std::reverse(loop.curves.begin(), loop.curves.end());
    for (TrimCurve& c : loop.curves) {
      std::reverse(c.points.begin(), c.points.end());
      std::reverse(c.weights.begin(), c.weights.end());
      const double a = c.knots.front(), b = c.knots.back();
      std::vector<double> knots;
      for (auto k = c.knots.rbegin(); k != c.knots.rend(); ++k) knots.push_back(a + b - *k);
      c.knots = knots;
    }
  }
  return scene;
}

// GLU's vertices of the plate against the closed form: the largest signed distance to the face
// (negative inside) and how many lie deeper than `depth` in the hole.
std::pair<double, int> against_closed_form(const SurfaceResult& r, double depth) {
  const TrimmedPlateShape shape;
  double worst = -INFINITY;
  int in_hole = 0;
  for (std::size_t k = 0; k < r.samples.count(); ++k) {
    const double u = r.samples.u_of(k), v = r.samples.v_of(k);
    worst = std::max(worst, test::trimmed_plate_signed_distance(shape, u, v));
    in_hole +=
        std::hypot(u - shape.hole_center_u, v - shape.hole_center_v) < shape.hole_radius - depth;
  }
  return {worst, in_hole};
}

TEST(GluNurbsTrims, TessellationOfTheTrimmedPlateKeepsOutOfTheHoleAndTheCorners) {
  if (!glu().probe().available) GTEST_SKIP() << glu().probe().reason;
  // GLU approximates the trim curves by chords of its own choosing, and puts vertices where the
  // chords cross its Bezier patches' edges: on the chords, inside an arc by up to the sagitta.
  // Measured: 4.1e-3 deep in the hole of radius 0.2 (chords of about 0.4 rad, some 16 per circle
  // at 64x64), 4e-8 outside the rounded rectangle. A vertex of the untrimmed surface lies
  // anywhere up to 0.2 deep.
  constexpr double kChordTolerance = 0.01;
  const Scene plate = trimmed_plate_scene();
  const EvalResult trimmed = run(plate, 64, 64);
  ASSERT_EQ(trimmed.surfaces.size(), 1u);
  ASSERT_GT(trimmed.surfaces[0].samples.count(), 1000u);
  const auto [worst, in_hole] = against_closed_form(trimmed.surfaces[0], kChordTolerance);
  EXPECT_EQ(in_hole, 0);
  EXPECT_LT(worst, kChordTolerance);

  // Not vacuous: the same plate without its trim has vertices deep in the hole and outside.
  Scene untrimmed = plate;
  untrimmed.surfaces[0].trim.reset();
  const auto [untrimmed_worst, untrimmed_in_hole] =
      against_closed_form(run(untrimmed, 64, 64).surfaces[0], kChordTolerance);
  EXPECT_GT(untrimmed_in_hole, 100);
  EXPECT_GT(untrimmed_worst, 0.01);

  // GLU's rule is orientation's (the left of each curve is kept); the loops are oriented by
  // their nesting first, so loops given the other way round tessellate to the same vertices.
  const EvalResult backwards = run(reversed_plate(), 64, 64);
  const SurfaceResult& a = trimmed.surfaces[0];
  const SurfaceResult& b = backwards.surfaces[0];
  std::set<std::pair<double, double>> uv_a, uv_b;
  for (std::size_t k = 0; k < a.samples.count(); ++k)
    uv_a.insert({a.samples.u_of(k), a.samples.v_of(k)});
  for (std::size_t k = 0; k < b.samples.count(); ++k)
    uv_b.insert({b.samples.u_of(k), b.samples.v_of(k)});
  EXPECT_EQ(uv_a, uv_b);
}

// GLU's trim tessellator converts each Bézier arc to the power basis through a table of orders
// 1..8 and reads past it for a degree-8 curve (bearing.iges face-163: SIGSEGV in evaluate).
// Degree 7, the last order of the table, tessellates and keeps the face: no vertex lies clearly
// outside the loop by the reference classifier (GLU's chords cut inside arcs, never far out);
// degree 8 is refused in prepare, naming the curve and the limit, before GLU sees it.
TEST(GluNurbsTrims, TrimCurvesUpToDegree7AndRefusesHigherBeforeGluCrashes) {
  if (!glu().probe().available) GTEST_SKIP() << glu().probe().reason;
  const Scene seven = test::high_degree_trim_scene(7);
  const EvalResult r = run(seven, 64, 64);
  ASSERT_EQ(r.surfaces.size(), 1u);
  const SurfaceResult& drawn = r.surfaces[0];
  ASSERT_GT(drawn.samples.count(), 500u);
  const TrimClassification exact =
      classify_trim_samples(*seven.surfaces[0].trim, drawn.samples, true, TrimScalar::long_double);
  std::size_t outside = 0;
  for (std::size_t k = 0; k < drawn.samples.count(); ++k)
    outside += exact.inside[k] == 0 && exact.distance[k] > 0.01;
  EXPECT_EQ(outside, 0u);

  for (int degree : {8, 15}) {
    auto strategy = glu().create(StrategyOptions{});
    Sampling grid;
    grid.grid_u = grid.grid_v = 16;
    try {
      strategy->prepare(test::high_degree_trim_scene(degree),
                        EvalRequest{grid, Precision::f32, false});
      ADD_FAILURE() << "degree " << degree << " not refused";
    } catch (const RefusedError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(fmt::format("trim.loops[0].curves[0].degree = {}", degree)),
                std::string::npos)
          << what;
      EXPECT_NE(what.find("up to degree 7"), std::string::npos) << what;
    }
  }
}

TEST(GluNurbsTrims, RecordsSayUntrimmedAndScoreTheTrimmedTessellation) {
  if (!glu().probe().available) GTEST_SKIP() << glu().probe().reason;
  // GLU chooses its samples and returns no classification of them: its records are "untrimmed"
  // (no misclassification figure), the errors over the vertices the reference puts inside.
  ReferenceCache references;
  Sampling grid;
  grid.grid_u = grid.grid_v = 32;
  const Record r = measure(glu(), {}, trimmed_plate_scene(),
                           EvalRequest{grid, Precision::f32, false}, 1, references);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_EQ(r.trimming, "untrimmed");
  ASSERT_TRUE(r.accuracy && r.accuracy->trim);
  EXPECT_FALSE(r.accuracy->trim->misclassified);
  EXPECT_GT(r.accuracy->trim->inside, 0u);
}

}  // namespace
}  // namespace nurbs
