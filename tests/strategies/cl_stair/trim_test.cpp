// cl-stair trims: classify.cl (the single-source direct-trimming classifier compiled as OpenCL C)
// against the reference classifier on trimmed-plate and the hammer, grid and span grid, f32 and
// (trimmed-plate) f64.
#include "tests/strategies/trim_direct/strategy_trim_check.h"

namespace nurbs {
namespace {

TEST(cl_stair_trim, TrimmedPlateExact) {
  test::expect_trimmed_plate_exact("cl-stair");
}
TEST(cl_stair_trim, HammerExact) {
  test::expect_hammer_exact("cl-stair");
}
TEST(cl_stair_trim, OptionsRefused) {
  test::expect_strategy_refuses_trim_options("cl-stair");
}

}  // namespace
}  // namespace nurbs
