// many-ducks-N (scenes/many_ducks.h): the duck's surfaces N times, apart, with every third duck's
// surfaces trimmed; the trimmed faces are checked against the trimmed plate's closed form mapped
// onto each surface's domain, not against the classifier alone.
#include "scenes/many_ducks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../cli/run_cli.h"
#include "reference/trim_classify.h"
#include "scenes/builtin_scenes.h"
#include "tests/scenes/trimmed_plate_closed_form.h"

namespace nurbs {
namespace {

TEST(ManyDucksScene, NCopiesOfTheDuckEveryThirdTrimmed) {
  const Scene duck = *make_builtin_scene("duck");
  const Scene scene = *make_builtin_scene("many-ducks-7");
  EXPECT_EQ(scene.name, "many-ducks-7");
  ASSERT_EQ(scene.surfaces.size(), 7 * duck.surfaces.size());
  std::array<double, 2> previous_low{-INFINITY, -INFINITY};
  for (int k = 0; k < 7; ++k)
    for (std::size_t i = 0; i < duck.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[k * duck.surfaces.size() + i];
      const Surface& d = duck.surfaces[i];
      EXPECT_EQ(s.trim.has_value(), k % 3 == 0) << s.name;
      EXPECT_EQ(s.knots_u, d.knots_u);
      EXPECT_EQ(s.weights, d.weights);
      // A translation of the duck's surface: every point moved by the same vector.
      const double dx = s.points[0][0] - d.points[0][0], dy = s.points[0][1] - d.points[0][1];
      for (std::size_t p = 0; p < d.points.size(); ++p) {
        EXPECT_DOUBLE_EQ(s.points[p][0] - d.points[p][0], dx);
        EXPECT_DOUBLE_EQ(s.points[p][1] - d.points[p][1], dy);
        EXPECT_EQ(s.points[p][2], d.points[p][2]);
      }
      if (i == 0) {
        // Ducks are laid out row by row: never two at the same place.
        EXPECT_NE((std::array<double, 2>{dx, dy}), previous_low);
        previous_low = {dx, dy};
      }
    }
  EXPECT_TRUE(scene.has_trims());
  EXPECT_TRUE(make_builtin_scene("many-ducks-1")->has_trims());
  EXPECT_FALSE(make_builtin_scene("many-ducks-0"));
  EXPECT_FALSE(make_builtin_scene("many-ducks-" + std::to_string(kMaxManyDucks + 1)));
}

TEST(ManyDucksScene, TrimsAreThePlatesLoopsOnEachDomainAsTheClosedFormSays) {
  const Scene scene = *make_builtin_scene("many-ducks-1");
  const TrimmedPlateShape shape;
  for (const Surface& s : scene.surfaces) {
    ASSERT_TRUE(s.trim);
    Sampling grid;
    grid.grid_u = grid.grid_v = 64;  // k / 63: off the straight sides at 0.05 and 0.95
    Scene one{"one", "", {s}};
    const SurfaceSamples samples = sample_parameters(one, grid)[0];
    const TrimClassification c =
        classify_trim_samples(*s.trim, samples, false, TrimScalar::long_double, 1);
    std::size_t inside = 0, checked = 0;
    for (std::size_t k = 0; k < samples.count(); ++k) {
      const double u = (samples.u_of(k) - s.u_min()) / (s.u_max() - s.u_min());
      const double v = (samples.v_of(k) - s.v_min()) / (s.v_max() - s.v_min());
      const double d = test::trimmed_plate_signed_distance(shape, u, v);
      if (std::abs(d) < 1e-9) continue;  // on the boundary: rounding decides
      ++checked;
      inside += d < 0;
      EXPECT_EQ(c.inside[k], d < 0 ? 1 : 0) << s.name << " at " << u << ", " << v;
    }
    EXPECT_GT(checked, 4000u);
    // Both sides of the boundary are sampled: the comparison above is not vacuous.
    EXPECT_GT(inside, checked / 2);
    EXPECT_LT(inside, checked);
  }
}

TEST(ManyDucksScene, ListedByTheCli) {
  const test::CliResult r = test::run_cli({"list"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("many-ducks-64"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace nurbs
