// cpu-coxdeboor trims: classify() classifies its own samples (the reference's classifier in
// double) and read_back() returns the mask, checked here against the closed form of the built-in
// trimmed-plate's face (a rounded rectangle minus a circle), not against the classifier.
#include <gtest/gtest.h>

#include <cmath>

#include "strategies/registry.h"
#include "tests/scenes/trimmed_plate_closed_form.h"

namespace nurbs {
namespace {

using test::expect_mask_is_the_closed_form;
using test::trimmed_plate_signed_distance;

std::unique_ptr<Strategy> coxdeboor() {
  return find_strategy("cpu-coxdeboor")->create({});
}

TEST(CpuCoxDeBoorTrim, MaskIsTheFacesClosedForm) {
  const TrimmedPlateShape shape;
  Scene scene = trimmed_plate_scene(shape);
  scene.surfaces.push_back(scene.surfaces[0]);  // the same plate untrimmed: no mask
  scene.surfaces[1].trim.reset();
  ASSERT_TRUE(find_strategy("cpu-coxdeboor")->capabilities().trims);
  for (Precision precision : {Precision::f32, Precision::f64}) {
    Sampling grid;
    grid.grid_u = 64;  // k/63, j/46: no sample on the frame's straight sides
    grid.grid_v = 47;
    auto strategy = coxdeboor();
    strategy->prepare(scene, EvalRequest{grid, precision, false});
    strategy->evaluate();
    EXPECT_TRUE(strategy->read_back().surfaces[0].inside.empty()) << "no mask before classify()";
    ASSERT_TRUE(strategy->classify());
    const EvalResult result = strategy->read_back();
    const SurfaceResult& r = result.surfaces[0];
    ASSERT_EQ(r.inside.size(), r.samples.count());
    EXPECT_TRUE(result.surfaces[1].inside.empty());
    const auto [inside, checked] = expect_mask_is_the_closed_form(shape, r.samples, r.inside);
    EXPECT_GT(checked, 64u * 47 - 10);
    // About the closed-form area's share of the samples: the mask is not all one answer.
    EXPECT_NEAR(static_cast<double>(inside) / checked, shape.inside_area(), 0.05);

    strategy->prepare(scene, EvalRequest{grid, precision, false});
    EXPECT_TRUE(strategy->read_back().surfaces[0].inside.empty()) << "prepare() starts over";
  }
}

TEST(CpuCoxDeBoorTrim, ExplicitSamplesAreClassifiedToo) {
  const TrimmedPlateShape shape;
  const Scene scene = trimmed_plate_scene(shape);
  Sampling list;
  list.mode = SamplingMode::explicit_list;
  // Hole centre, a point just outside the hole, a rounded corner's cut-off tip, mid-frame.
  list.explicit_uv = {{{0.5, 0.5}, {0.5, 0.71}, {0.06, 0.06}, {0.2, 0.5}}};
  auto strategy = coxdeboor();
  strategy->prepare(scene, EvalRequest{list, Precision::f64, false});
  strategy->evaluate();
  strategy->classify();
  EXPECT_EQ(strategy->read_back().surfaces[0].inside, (std::vector<std::uint8_t>{0, 1, 0, 1}));
  for (const auto& [u, v] : list.explicit_uv[0])
    EXPECT_GT(std::abs(trimmed_plate_signed_distance(shape, u, v)), 1e-3)
        << "well away from the boundary";
}

}  // namespace
}  // namespace nurbs
