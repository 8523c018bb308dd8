// vk-ksquad on the Vulkan device (lavapipe here: CPU figures) at degrees 10, 12 and 15: positions
// and normals (stair_derivative) against the reference. No device limit depends on the degree:
// the control points, constants and tables are storage buffers (not bounded by
// maxTessellationPatchSize, one control point per patch), the push constants (Mode) and the
// tessellation levels do not grow with it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

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

// vk-constants=device (the default: ksquad_constants.comp, the single-source stair_constants as
// GLSL) against vk-constants=host (its C++ build, uploaded): the same points within 4 float ulps
// of the scene's largest coordinate (Vulkan lets a division be 2.5 ulps off; lavapipe's are
// correctly rounded, and measured the points are bit-identical), both within the 16-ulp bound
// against the reference, in every mapping that reads the constants. Wrong constants (a span, a
// degree or an offset off by one) move points by far more than that.
TEST(vk_ksquad_degree, ConstantsOnTheDeviceMatchTheHostBuild) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  struct Case {
    Scene scene;
    std::string mode;
  };
  std::vector<Case> cases;
  for (const char* name : {"teapot", "clustered"})
    for (const char* mode : {"uniform", "adaptive"})
      cases.push_back({*make_builtin_scene(name), mode});
  cases.push_back({workload_scene(12, 16, 16, 1), "uniform"});
  Sampling grid;
  grid.grid_u = grid.grid_v = 17;
  for (const Case& c : cases) {
    SCOPED_TRACE(c.scene.name + " " + c.mode);
    std::vector<EvalResult> results;
    for (const char* where : {"host", "device"}) {
      StrategyOptions options;
      options.extra = {{"vk-mode", c.mode}, {"vk-constants", where}};
      const auto strategy = make_vk_ksquad(options);
      strategy->prepare(c.scene, EvalRequest{grid, Precision::f32, false});
      strategy->evaluate();
      results.push_back(strategy->read_back());
      EXPECT_EQ(strategy->device().details.at("vk_constants"), where);
      // Adaptive mode's samples are the tessellator's: the reference at those.
      std::vector<SurfaceSamples> samples;
      for (const SurfaceResult& r : results.back().surfaces) samples.push_back(r.samples);
      const Accuracy acc =
          measure_accuracy(c.scene, results.back(), evaluate_reference(c.scene, samples, false));
      EXPECT_LE(acc.max_ulp, 16.0) << where;
    }
    const double ulp = std::numeric_limits<float>::epsilon() * c.scene.largest_coordinate();
    double worst = 0;
    std::size_t identical = 0, points = 0;
    ASSERT_EQ(results[0].surfaces.size(), results[1].surfaces.size());
    for (std::size_t i = 0; i < results[0].surfaces.size(); ++i) {
      const PointArray& host = results[0].surfaces[i].positions;
      const PointArray& device = results[1].surfaces[i].positions;
      ASSERT_EQ(host.size(), device.size());
      for (std::size_t k = 0; k < host.size(); ++k) {
        double d = 0;
        for (int axis = 0; axis < 3; ++axis)
          d = std::max(
              d, std::abs(double(host.f32()[3 * k + axis]) - double(device.f32()[3 * k + axis])));
        worst = std::max(worst, d);
        identical += d == 0;
        ++points;
      }
    }
    std::printf(
        "vk-constants device vs host, %s %s: %zu of %zu points identical, worst %.3g ulps\n",
        c.scene.name.c_str(), c.mode.c_str(), identical, points, worst / ulp);
    EXPECT_GT(points, 0u);
    EXPECT_LE(worst, 4 * ulp);
  }
}

}  // namespace
}  // namespace nurbs
