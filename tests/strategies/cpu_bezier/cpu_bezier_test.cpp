// cpu-bezier: f64 agrees with cpu-coxdeboor to double precision; update_control_points() really
// re-decomposes (the result after an update is the reference of the moved scene, not of the old
// one); the thread count changes nothing; a structural change is refused.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

#include "harness/metrics.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "tests/reference/test_support.h"

namespace nurbs {
namespace {

using test::grid;

EvalResult run(const std::string& name, const Scene& scene, const EvalRequest& request,
               int threads = 0) {
  StrategyOptions options;
  options.threads = threads;
  auto s = find_strategy(name)->create(options);
  s->prepare(scene, request);
  s->evaluate();
  return s->read_back();
}

TEST(CpuBezier, AgreesWithCoxDeBoorInDoublePrecision) {
  for (const char* scene_name : {"patch144", "torus", "degree-9", "creases", "duck"}) {
    const Scene scene = *make_builtin_scene(scene_name);
    Sampling span;
    span.mode = SamplingMode::span_grid;
    span.span_steps = 5;
    const EvalRequest request{span, Precision::f64, false};
    const EvalResult bezier = run("cpu-bezier", scene, request);
    const EvalResult cox = run("cpu-coxdeboor", scene, request);
    const double tolerance = 64 * DBL_EPSILON * scene.largest_coordinate();
    for (std::size_t i = 0; i < bezier.surfaces.size(); ++i)
      for (std::size_t k = 0; k < bezier.surfaces[i].positions.size(); ++k)
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(bezier.surfaces[i].positions[k][c], cox.surfaces[i].positions[k][c],
                      tolerance)
              << scene_name << " surface " << i << " sample " << k;
  }
}

// Every control point moved by a different amount (so every Bézier point changes).
Scene moved(const Scene& base) {
  Scene s = base;
  for (Surface& surface : s.surfaces)
    for (Point3& p : surface.points) {
      p[2] += 0.25 * std::sin(3 * p[0]) + 0.125 * std::cos(2 * p[1]);
      p[0] += 0.0625 * p[1];
    }
  return s;
}

TEST(CpuBezier, UpdateControlPointsRedecomposes) {
  const Scene before = *make_builtin_scene("patch144");
  const Scene after = moved(before);
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const EvalRequest request{grid(17, 13), precision, true};
    auto strategy = find_strategy("cpu-bezier")->create(StrategyOptions{});
    strategy->prepare(before, request);
    strategy->evaluate();
    strategy->update_control_points(after);
    strategy->evaluate();
    const EvalResult result = strategy->read_back();
    const auto samples = sample_parameters(after, request.sampling);
    const Accuracy moved_acc =
        measure_accuracy(after, result, evaluate_reference(after, samples, true));
    const Accuracy stale_acc =
        measure_accuracy(before, result, evaluate_reference(before, samples, true));
    const double budget = precision == Precision::f32 ? 32.0 : 64.0 * DBL_EPSILON / FLT_EPSILON;
    EXPECT_LE(moved_acc.max_ulp, budget) << to_string(precision);
    EXPECT_LE(*moved_acc.max_normal_angle_deg, precision == Precision::f32 ? 1.0 : 1e-6);
    // Against the old scene the result is off by the motion itself (~0.1 model units).
    EXPECT_GT(stale_acc.max_abs, 0.05) << to_string(precision);
    // And identical to a fresh prepare on the moved scene.
    const EvalResult fresh = run("cpu-bezier", after, request);
    for (std::size_t k = 0; k < fresh.surfaces[0].positions.size(); ++k)
      ASSERT_EQ(fresh.surfaces[0].positions[k], result.surfaces[0].positions[k]) << k;
  }
}

TEST(CpuBezier, UpdateWithAnotherStructureIsRefused) {
  const Scene base = *make_builtin_scene("patch144");
  auto strategy = find_strategy("cpu-bezier")->create(StrategyOptions{});
  strategy->prepare(base, EvalRequest{grid(4, 4), Precision::f32, false});
  EXPECT_THROW(strategy->update_control_points(*make_builtin_scene("many-2")),
               std::invalid_argument);
  EXPECT_THROW(strategy->update_control_points(*make_builtin_scene("tan16")),
               std::invalid_argument);
}

TEST(CpuBezier, ThreadCountGivesIdenticalResults) {
  for (const char* scene_name : {"many-16", "teapot"}) {
    const Scene scene = *make_builtin_scene(scene_name);
    const EvalRequest request{grid(23, 19), Precision::f32, true};
    const EvalResult one = run("cpu-bezier", scene, request, 1);
    const EvalResult two = run("cpu-bezier", scene, request, 2);
    for (std::size_t i = 0; i < one.surfaces.size(); ++i)
      for (std::size_t k = 0; k < one.surfaces[i].positions.size(); ++k) {
        ASSERT_EQ(one.surfaces[i].positions[k], two.surfaces[i].positions[k]) << scene_name;
        ASSERT_EQ(one.surfaces[i].normals[k], two.surfaces[i].normals[k]) << scene_name;
      }
  }
}

}  // namespace
}  // namespace nurbs
