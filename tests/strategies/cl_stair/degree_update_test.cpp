// cl-stair on the OpenCL device (PoCL here: CPU figures): degrees 10, 12 and 15 against the
// reference, and the deforming path -- the program built once, update_control_points landing on
// the moved surface.
#include <gtest/gtest.h>

#include <cstdio>

#include "harness/metrics.h"
#include "harness/runner.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "scenes/deforming.h"
#include "strategies/registry.h"

namespace nurbs {
namespace {

class cl_stair : public ::testing::Test {
 protected:
  void SetUp() override {
    const Availability a = entry().probe();
    if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  }
  static const StrategyEntry& entry() { return *find_strategy("cl-stair"); }
};

// 33 x 33 on the [0, 1] domain: every parameter i/32 is exact in float, so the error is the
// evaluation's, not the parameter's rounding.
Sampling grid33() {
  Sampling s;
  s.grid_u = s.grid_v = 33;
  return s;
}

Accuracy run(Strategy& strategy, const Scene& scene, Precision precision) {
  strategy.prepare(scene, EvalRequest{grid33(), precision, false});
  strategy.evaluate();
  const EvalResult result = strategy.read_back();
  return measure_accuracy(scene, result,
                          evaluate_reference(scene, sample_parameters(scene, grid33()), false));
}

std::string detail(const Strategy& strategy, const std::string& key) {
  const auto details = strategy.device().details;
  const auto it = details.find(key);
  return it == details.end() ? "" : it->second;
}

// The degree-N scenes' 16x16 net at degree 10, 12, 15 (uniform clamped knots). Bounds, in
// float32 ulps of the largest coordinate (metrics.h): f32 16, f64 5e-8 (~27 double ulps);
// measured on PoCL: f32 1.9 / 2.1 / 2.4, f64 4.4e-9 / 3.0e-9 / 5.9e-9 at degree 10 / 12 / 15.
TEST_F(cl_stair, HighDegreesMatchTheReference) {
  EXPECT_EQ(entry().capabilities().max_degree, 15);
  const auto strategy = entry().create(StrategyOptions{});
  for (int degree : {10, 12, 15}) {
    const Scene scene = workload_scene(degree, 16, 16, 1);
    for (Precision precision : {Precision::f32, Precision::f64}) {
      const Accuracy acc = run(*strategy, scene, precision);
      std::printf("cl-stair degree %d %s: max_ulp %.3g (f32 ulps), max_rel %.3g\n", degree,
                  to_string(precision).data(), acc.max_ulp, acc.max_rel);
      EXPECT_EQ(acc.non_finite, 0u);
      EXPECT_LE(acc.max_ulp, precision == Precision::f32 ? 16.0 : 5e-8) << degree;
    }
  }
  std::printf("cl-stair degree 15 f64: local memory %s bytes, private memory %s bytes\n",
              detail(*strategy, "local_mem_bytes").c_str(),
              detail(*strategy, "private_mem_bytes").c_str());
  // One program per precision for the six prepare() calls.
  EXPECT_EQ(detail(*strategy, "program_builds"), "2");
}

// 003 §5: a deforming frame re-sends only the control points. The last frame must be the moved
// surface (a stale net misses it by the wave's amplitude, over 1000 ulps: deforming_test's
// AnUpdateThatDoesNothingIsCaught), and no frame rebuilds the program. Bounds as above (measured
// 1.5 and 3.3e-9).
TEST_F(cl_stair, DeformingUpdatesLandOnTheMovedSurfaceWithoutRebuilding) {
  EXPECT_TRUE(entry().capabilities().updates_control_points);
  const Scene scene = *make_builtin_scene("patch144");
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const Record r = measure_deforming(entry(), StrategyOptions{}, scene,
                                       EvalRequest{grid33(), precision, false}, 4,
                                       ReferencePrecision::long_double);
    ASSERT_EQ(r.status, Status::ok) << r.reason;
    ASSERT_TRUE(r.accuracy.has_value());
    std::printf("cl-stair deforming patch144 %s: last frame max_ulp %.3g\n",
                to_string(precision).data(), r.accuracy->max_ulp);
    EXPECT_LE(r.accuracy->max_ulp, precision == Precision::f32 ? 16.0 : 5e-8);
    EXPECT_TRUE(r.extra_phases.count("frame_update"));
    EXPECT_FALSE(r.extra_phases.count("frame_prepare"));
    EXPECT_EQ(r.device.details.at("program_builds"), "1");
  }
}

// The same through the interface directly: an update moves the result to the new frame, prepare
// again keeps the program, and a net of another size is an error, not a silent partial upload.
TEST_F(cl_stair, UpdateMovesTheResultAndKeepsTheProgram) {
  const Scene base = *make_builtin_scene("patch144");
  const auto strategy = entry().create(StrategyOptions{});
  const EvalRequest request{grid33(), Precision::f64, false};
  strategy->prepare(deformed_scene(base, 0), request);
  const Scene moved = deformed_scene(base, 5);
  strategy->update_control_points(moved);
  strategy->evaluate();
  const Accuracy acc =
      measure_accuracy(moved, strategy->read_back(),
                       evaluate_reference(moved, sample_parameters(moved, grid33()), false));
  EXPECT_LE(acc.max_ulp, 5e-8);
  strategy->prepare(moved, request);
  EXPECT_EQ(detail(*strategy, "program_builds"), "1");
  EXPECT_THROW(strategy->update_control_points(*make_builtin_scene("degree-3")),
               std::invalid_argument);
}

}  // namespace
}  // namespace nurbs
