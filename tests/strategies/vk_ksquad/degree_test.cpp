// vk-ksquad on the Vulkan device (lavapipe here: CPU figures) at degrees 10, 12 and 15: positions
// and normals (stair_derivative) against the reference. No device limit depends on the degree:
// the control points, constants and tables are storage buffers (not bounded by
// maxTessellationPatchSize, one control point per patch), the push constants (Mode) and the
// tessellation levels do not grow with it.
#include <gtest/gtest.h>

#include <cstdio>

#include "harness/metrics.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"

namespace nurbs {
namespace {

// The degree-N scenes' 16x16 net at degree 10, 12, 15 (uniform clamped knots), 33 x 33 samples
// (exact in float on [0, 1]). Bounds: 16 float32 ulps and 0.01 degree for normals; measured on
// lavapipe 2.6 / 2.7 / 2.5 ulps and 1.1e-4 / 7.8e-5 / 1.0e-4 degree at degree 10 / 12 / 15.
TEST(vk_ksquad_degree, HighDegreesMatchTheReference) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  EXPECT_EQ(find_strategy("vk-ksquad")->capabilities().max_degree, 15);
  const auto strategy = make_vk_ksquad(StrategyOptions{});
  Sampling grid;
  grid.grid_u = grid.grid_v = 33;
  for (int degree : {10, 12, 15}) {
    const Scene scene = workload_scene(degree, 16, 16, 1);
    strategy->prepare(scene, EvalRequest{grid, Precision::f32, true});
    strategy->evaluate();
    const EvalResult result = strategy->read_back();
    const Accuracy acc = measure_accuracy(
        scene, result, evaluate_reference(scene, sample_parameters(scene, grid), true));
    std::printf("vk-ksquad degree %d f32: max_ulp %.3g, normals %.3g deg\n", degree, acc.max_ulp,
                acc.max_normal_angle_deg.value_or(-1));
    EXPECT_EQ(acc.non_finite, 0u);
    EXPECT_LE(acc.max_ulp, 16.0) << degree;
    ASSERT_TRUE(acc.max_normal_angle_deg.has_value());
    EXPECT_LE(*acc.max_normal_angle_deg, 0.01) << degree;
  }
}

}  // namespace
}  // namespace nurbs
