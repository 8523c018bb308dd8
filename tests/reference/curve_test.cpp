// reference/curve.h: A4.1 on homogeneous points against equations evaluated independently (a
// rational quadratic quarter circle lies on the unit circle; a clamped curve starts and ends at
// its end control points), and validate_curve's one-line errors.
#include "reference/curve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "reference/validation.h"

namespace nurbs {
namespace {

// Quarter circle: (1,0), (1,1) with weight sqrt(2)/2, (0,1); Piegl & Tiller Ex. 7.1.
Curve quarter_circle() {
  const double w = std::sqrt(0.5);
  Curve c;
  c.degree = 2;
  c.knots = {0, 0, 0, 1, 1, 1};
  c.homogeneous = {{1, 0, 0, 1}, {w, w, 0, w}, {0, 1, 0, 1}};
  return c;
}

TEST(CurvePoint, RationalQuarterCircleLiesOnTheUnitCircle) {
  const Curve c = quarter_circle();
  for (int i = 0; i <= 100; ++i) {
    const double u = i / 100.0;
    const Vec3<double> p = curve_point(c, u);
    EXPECT_NEAR(std::hypot(p[0], p[1]), 1.0, 4e-16) << "u=" << u;
    EXPECT_EQ(p[2], 0.0);
  }
  const Vec3<double> start = curve_point(c, 0.0), end = curve_point(c, 1.0);
  EXPECT_EQ(start[0], 1.0);
  EXPECT_EQ(start[1], 0.0);
  EXPECT_EQ(end[0], 0.0);
  EXPECT_EQ(end[1], 1.0);
  // Its midpoint is at 45 degrees: (sqrt(2)/2, sqrt(2)/2), within a few double ulps (1.1e-16 here).
  const Vec3<double> mid = curve_point(c, 0.5);
  EXPECT_NEAR(mid[0], std::sqrt(0.5), 4e-16);
  EXPECT_NEAR(mid[1], std::sqrt(0.5), 4e-16);
}

std::string error_of(const Curve& c) {
  try {
    validate_curve(c, "test");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ValidateCurve, NamesFieldIndexAndValue) {
  EXPECT_EQ(error_of(quarter_circle()), "");
  Curve short_knots = quarter_circle();
  short_knots.knots.pop_back();
  EXPECT_NE(error_of(short_knots).find("knots length = 5"), std::string::npos)
      << error_of(short_knots);
  Curve negative = quarter_circle();
  negative.homogeneous[1][3] = -1;
  EXPECT_NE(error_of(negative).find("points[1][3] = -1"), std::string::npos) << error_of(negative);
  Curve infinite = quarter_circle();
  infinite.homogeneous[0][2] = INFINITY;
  EXPECT_NE(error_of(infinite).find("points[0][2] = inf"), std::string::npos) << error_of(infinite);
  Curve degree0 = quarter_circle();
  degree0.degree = 0;
  EXPECT_NE(error_of(degree0).find("degree = 0"), std::string::npos) << error_of(degree0);
}

}  // namespace
}  // namespace nurbs
