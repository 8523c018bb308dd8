// cpu-tensor: thread count changes nothing (every row is computed by one thread with the same
// operations), f64 agrees with cpu-coxdeboor to double precision, explicit lists are refused.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <map>
#include <string>

#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs {
namespace {

EvalResult run(const std::string& name, const Scene& scene, const EvalRequest& request, int threads,
               std::map<std::string, std::string> extra = {}) {
  StrategyOptions options;
  options.threads = threads;
  options.extra = std::move(extra);
  auto s = find_strategy(name)->create(options);
  s->prepare(scene, request);
  s->evaluate();
  return s->read_back();
}

TEST(CpuTensor, ThreadCountGivesIdenticalResults) {
  for (const char* scene_name : {"patch144", "many-16", "sphere"}) {
    const Scene scene = *make_builtin_scene(scene_name);
    for (Precision precision : {Precision::f32, Precision::f64}) {
      Sampling grid;
      grid.grid_u = 37;
      grid.grid_v = 41;
      const EvalRequest request{grid, precision, true};
      const EvalResult one = run("cpu-tensor", scene, request, 1);
      for (int threads : {2, 3}) {
        const EvalResult many = run("cpu-tensor", scene, request, threads);
        for (std::size_t i = 0; i < one.surfaces.size(); ++i)
          for (std::size_t k = 0; k < one.surfaces[i].positions.size(); ++k) {
            ASSERT_EQ(one.surfaces[i].positions[k], many.surfaces[i].positions[k]) << scene_name;
            ASSERT_EQ(one.surfaces[i].normals[k], many.surfaces[i].normals[k]) << scene_name;
          }
      }
    }
  }
}

TEST(CpuTensor, AgreesWithCoxDeBoorInDoublePrecision) {
  for (const char* scene_name : {"patch144", "torus", "degree-7", "creases"}) {
    const Scene scene = *make_builtin_scene(scene_name);
    Sampling span;
    span.mode = SamplingMode::span_grid;
    span.span_steps = 5;
    const EvalRequest request{span, Precision::f64, false};
    const EvalResult tensor = run("cpu-tensor", scene, request, 0);
    const EvalResult cox = run("cpu-coxdeboor", scene, request, 0);
    const double tolerance = 64 * DBL_EPSILON * scene.largest_coordinate();
    for (std::size_t i = 0; i < tensor.surfaces.size(); ++i)
      for (std::size_t k = 0; k < tensor.surfaces[i].positions.size(); ++k)
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(tensor.surfaces[i].positions[k][c], cox.surfaces[i].positions[k][c],
                      tolerance)
              << scene_name << " sample " << k;
  }
}

// simd=off runs the same kernels compiled without vectorisation: the same sums in the same order,
// so the results agree to the last bits FMA contraction may change (the AVX2/AVX-512 clones fuse
// multiply-adds, the baseline build cannot).
TEST(CpuTensor, SimdOffAgreesAndSaysSo) {
  const Scene scene = *make_builtin_scene("patch144");
  Sampling grid;
  grid.grid_u = 33;
  grid.grid_v = 29;
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const EvalRequest request{grid, precision, true};
    const EvalResult simd = run("cpu-tensor", scene, request, 2);
    const EvalResult scalar = run("cpu-tensor", scene, request, 2, {{"simd", "off"}});
    const double eps = precision == Precision::f32 ? FLT_EPSILON : DBL_EPSILON;
    const double tolerance = 8 * eps * scene.largest_coordinate();
    for (std::size_t k = 0; k < simd.surfaces[0].positions.size(); ++k)
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(simd.surfaces[0].positions[k][c], scalar.surfaces[0].positions[k][c],
                    tolerance);
        ASSERT_NEAR(simd.surfaces[0].normals[k][c], scalar.surfaces[0].normals[k][c], 64 * eps);
      }
  }
  StrategyOptions off;
  off.extra["simd"] = "off";
  EXPECT_EQ(find_strategy("cpu-tensor")->create(off)->device().details.at("simd").rfind("off", 0),
            0u);
  off.extra["simd"] = "fast";
  EXPECT_THROW(find_strategy("cpu-tensor")->create(off), std::invalid_argument);
}

TEST(CpuTensor, RefusesExplicitLists) {
  const StrategyEntry& entry = *find_strategy("cpu-tensor");
  Sampling list;
  list.mode = SamplingMode::explicit_list;
  list.explicit_uv = {{{0.5, 0.5}}};
  const Scene scene = *make_builtin_scene("patch144");
  EXPECT_TRUE(
      refusal_reason(entry.capabilities(), scene, EvalRequest{list, Precision::f32, false}));
}

}  // namespace
}  // namespace nurbs
