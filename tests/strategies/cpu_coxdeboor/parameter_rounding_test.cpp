// Where a float32 evaluator's error comes from on tightly clustered knots: with spans of 1e-4 the
// float32 rounding of the parameter itself (ulp ~3e-8 near 0.3) moves the sample by ~3e-4 of a
// span, and the surface is steep there. Measured at the requested double (u, v) — as docs/design.md
// §Reference and accuracy says users see it — cpu-coxdeboor f32 exceeds 32 ulps; measured at the
// float-rounded (u, v) it is within the bound. This pins the cause down so nobody "fixes" the
// evaluator for it.
#include <gtest/gtest.h>

#include "harness/metrics.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs {
namespace {

TEST(CpuCoxDeBoorParameterRounding, ClusteredKnotErrorIsParameterRounding) {
  Scene scene = *make_builtin_scene("clustered");
  scene.surfaces[0].knots_v = {0,      0,      0,   0,   0.1, 0.2, 0.3, 0.3001,
                               0.3002, 0.3003, 0.7, 0.9, 1,   1,   1,   1};
  Sampling sampling;
  sampling.mode = SamplingMode::span_grid;
  sampling.span_steps = 3;
  auto strategy = find_strategy("cpu-coxdeboor")->create(StrategyOptions{});
  strategy->prepare(scene, EvalRequest{sampling, Precision::f32, false});
  strategy->evaluate();
  const EvalResult result = strategy->read_back();

  const auto samples = sample_parameters(scene, sampling);
  const Accuracy at_requested =
      measure_accuracy(scene, result, evaluate_reference(scene, samples, false));

  // The same surface with its knots rounded to float, sampled at float-rounded parameters: what
  // the float32 evaluator was actually able to represent.
  Scene rounded_scene = scene;
  for (double& k : rounded_scene.surfaces[0].knots_u) k = static_cast<float>(k);
  for (double& k : rounded_scene.surfaces[0].knots_v) k = static_cast<float>(k);
  auto rounded_samples = samples;
  for (double& u : rounded_samples[0].u) u = static_cast<float>(u);
  for (double& v : rounded_samples[0].v) v = static_cast<float>(v);
  const Accuracy at_rounded =
      measure_accuracy(scene, result, evaluate_reference(rounded_scene, rounded_samples, false));

  std::cout << "clustered 1e-4 spans, f32: " << at_requested.max_ulp
            << " ulps at the requested (u,v), " << at_rounded.max_ulp
            << " ulps at the float-rounded (u,v) and knots\n";
  EXPECT_GT(at_requested.max_ulp, 32.0);
  EXPECT_LE(at_rounded.max_ulp, 32.0);
}

}  // namespace
}  // namespace nurbs
