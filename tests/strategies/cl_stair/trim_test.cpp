// cl-stair trims: classify.cl (the single-source direct-trimming classifier compiled as OpenCL C)
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

TEST(cl_stair_trim, TrimmedPlateExact) {
  test::expect_strategy_trims_exactly("cl-stair", "trimmed-plate", grid(97), Precision::f32);
  test::expect_strategy_trims_exactly("cl-stair", "trimmed-plate", span_grid(16), Precision::f32);
  test::expect_strategy_trims_exactly("cl-stair", "trimmed-plate", grid(64), Precision::f64);
}

TEST(cl_stair_trim, HammerExact) {
  test::expect_strategy_trims_exactly("cl-stair", "hammer", grid(33), Precision::f32);
  test::expect_strategy_trims_exactly("cl-stair", "hammer", span_grid(3), Precision::f32);
}

TEST(cl_stair_trim, OptionsRefused) {
  test::expect_trim_options_refused("cl-stair");
}

}  // namespace
}  // namespace nurbs
