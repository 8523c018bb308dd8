// vk-ksquad trims: trim_classify.comp (the single-source direct-trimming classifier as GLSL)
// against the reference classifier on trimmed-plate and the hammer, grid and span grid.
#include "tests/strategies/trim_direct/strategy_trim_check.h"

namespace nurbs {
namespace {

Sampling grid(int n) {
  Sampling s;
  s.grid_u = n;
  s.grid_v = n + 3;
  return s;
}

Sampling span_grid(int steps) {
  Sampling s;
  s.mode = SamplingMode::span_grid;
  s.span_steps = steps;
  return s;
}

TEST(VkKsquadTrim, TrimmedPlateExact) {
  test::expect_strategy_trims_exactly("vk-ksquad", "trimmed-plate", grid(97), Precision::f32);
  test::expect_strategy_trims_exactly("vk-ksquad", "trimmed-plate", span_grid(16), Precision::f32);
}

TEST(VkKsquadTrim, HammerExact) {
  test::expect_strategy_trims_exactly("vk-ksquad", "hammer", grid(33), Precision::f32);
  test::expect_strategy_trims_exactly("vk-ksquad", "hammer", span_grid(3), Precision::f32);
}

TEST(VkKsquadTrim, OptionsRefused) { test::expect_trim_options_refused("vk-ksquad"); }

TEST(VkKsquadTrim, AdaptiveModeRefusesTrimmedScenes) {
  StrategyOptions o;
  o.extra["vk-mode"] = "adaptive";
  auto s = find_strategy("vk-ksquad")->create(o);
  EXPECT_THROW(s->prepare(*make_builtin_scene("trimmed-plate"), EvalRequest{grid(8)}),
               RefusedError);
}

}  // namespace
}  // namespace nurbs
