// cl-stair trims: classify.cl (the single-source direct-trimming classifier compiled as OpenCL C)
// against the reference classifier on trimmed-plate and the hammer, grid and span grid, f32 and
// (trimmed-plate) f64; trim curves of degree 9 and 15 (the device's TD_MAX_ORDER arrays).
#include "reference/nurbs_math.h"
#include "tests/scenes/high_degree_trim.h"
#include "tests/strategies/trim_direct/strategy_trim_check.h"

namespace nurbs {
namespace {

TEST(cl_stair_trim, TrimmedPlateExact) {
  test::expect_trimmed_plate_exact("cl-stair");
}
TEST(cl_stair_trim, HammerExact) {
  test::expect_hammer_exact("cl-stair");
}
TEST(cl_stair_trim, TrimCurvesOfDegree9And15Exact) {
  const Availability a = find_strategy("cl-stair")->probe();
  if (!a.available) GTEST_SKIP() << a.reason;
  for (int degree : {9, kMaxDegree}) {
    const Scene scene = test::high_degree_trim_scene(degree);
    test::expect_strategy_trims_exactly("cl-stair", scene, scene.surfaces[0].name,
                                        test::trim_grid(33), Precision::f32);
  }
}
TEST(cl_stair_trim, OptionsRefused) {
  test::expect_strategy_refuses_trim_options("cl-stair");
}

}  // namespace
}  // namespace nurbs
