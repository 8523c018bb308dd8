// The host half of 000 §4's trim texture (strategies/trim_texture/trim_polygons.h), GL-free: the
// trimmed-plate's hole is an exact rational circle, so its polygon can be checked against the
// circle itself: every vertex on the circle, every chord's sagitta within the tolerance, and not
// many more vertices than the fewest that meet it. Also the option parsing and the distance bound.
#include "strategies/trim_texture/trim_polygons.h"

#include <gtest/gtest.h>

#include <cmath>

#include "scenes/trimmed_plate.h"

namespace nurbs {
namespace {

class TrimTexturePolygons : public ::testing::TestWithParam<double> {};

TEST_P(TrimTexturePolygons, HoleCircleWithinTheChordalTolerance) {
  const TrimmedPlateShape shape;
  const Scene scene = trimmed_plate_scene(shape);
  const double tolerance = GetParam();
  const auto polygons = trim_texture::trim_polygons(*scene.surfaces[0].trim, tolerance);
  ASSERT_EQ(polygons.size(), 2u);  // the rounded rectangle and the hole
  const std::vector<Point2>& hole = polygons[1];
  const double r = shape.hole_radius;
  double worst_sagitta = 0;
  for (std::size_t j = 0; j < hole.size(); ++j) {
    const Point2& a = hole[j];
    const Point2& b = hole[(j + 1) % hole.size()];
    EXPECT_NEAR(std::hypot(a[0] - shape.hole_center_u, a[1] - shape.hole_center_v), r, 1e-12);
    const double mid = std::hypot(0.5 * (a[0] + b[0]) - shape.hole_center_u,
                                  0.5 * (a[1] + b[1]) - shape.hole_center_v);
    worst_sagitta = std::max(worst_sagitta, r - mid);
  }
  EXPECT_LE(worst_sagitta, tolerance * (1 + 1e-9));
  // The fewest chords of sagitta <= tol: pi / acos(1 - tol / r). The control-point test is
  // conservative and halves parameter ranges, so allow 4x that (plus the 4 pieces' ends).
  const double fewest = M_PI / std::acos(1 - tolerance / r);
  EXPECT_LE(static_cast<double>(hole.size()), 4 * fewest + 8) << hole.size() << " vertices";
  EXPECT_GE(static_cast<double>(hole.size()), fewest);
}

INSTANTIATE_TEST_SUITE_P(Tolerances, TrimTexturePolygons, ::testing::Values(1e-2, 1e-4, 1e-6),
                         [](const auto& info) {
                           return "trim_tolerance_1e_minus_" +
                                  std::to_string(static_cast<int>(-std::log10(info.param) + 0.5));
                         });

TEST(TrimTextureOptions, trim_defaults_and_values) {
  EXPECT_EQ(trim_texture::parse_options({}, "s").resolution, trim_texture::kDefaultResolution);
  StrategyOptions o;
  o.extra["trim-resolution"] = "4096";
  o.extra["trim-tolerance"] = "1e-3";
  const trim_texture::Options parsed = trim_texture::parse_options(o, "s");
  EXPECT_EQ(parsed.resolution, 4096);
  EXPECT_EQ(parsed.tolerance, 1e-3);
  o.extra["trim-resolution"] = "63";
  EXPECT_THROW(trim_texture::parse_options(o, "s"), std::invalid_argument);
}

// d = (1/2 + 2^-(s+1)) x texel diagonal + tolerance, by hand: a 64-texel unit square has texel
// diagonal sqrt(2)/64; a 4 x 3 domain at R = 100 has texels 0.04 x 0.03, diagonal 0.05.
TEST(TrimTextureOptions, trim_distance_is_half_a_texel_diagonal_and_snapping_plus_tolerance) {
  EXPECT_DOUBLE_EQ(trim_texture::misclassification_distance(1, 1, 64, 0, 8),
                   (0.5 + 1.0 / 512) * std::sqrt(2) / 64);
  EXPECT_DOUBLE_EQ(trim_texture::misclassification_distance(4, 3, 100, 0.01, 4),
                   0.05 * (0.5 + 1.0 / 32) + 0.01);
}

}  // namespace
}  // namespace nurbs
