#include "reference/curve.h"

#include <fmt/format.h>

#include <cmath>
#include <string>

#include "reference/surface_checker.h"
#include "reference/validation.h"

namespace nurbs {

void validate_curve(const Curve& c, std::string_view origin) {
  // SurfaceChecker names a surface in its messages; a curve passes as the surface 'curve', so its
  // errors read like a trim curve's ("...: surface 'curve' (#0): knots[3] = ...").
  Surface named;
  named.name = "curve";
  const SurfaceChecker check(named, 0, origin);
  check.check_degree("degree", c.degree);
  check.check_count("points", kLengthIndex, static_cast<std::int64_t>(c.homogeneous.size()),
                    c.degree, kMaxCountPerDirection);
  check.check_knots("knots", c.knots, c.degree, c.count());
  for (std::size_t k = 0; k < c.homogeneous.size(); ++k) {
    for (int i = 0; i < 3; ++i)
      if (!std::isfinite(c.homogeneous[k][i]))
        check.fail("points", fmt::format("{}][{}", k, i), format_number(c.homogeneous[k][i]),
                   "coordinates must be finite");
    if (!std::isfinite(c.homogeneous[k][3]) || !(c.homogeneous[k][3] > 0))
      check.fail("points", fmt::format("{}][3", k), format_number(c.homogeneous[k][3]),
                 "weights must be finite and > 0");
  }
}

Vec3<double> curve_point(const Curve& c, double u) {
  const Vec4<double> sum =
      curve_point_homogeneous(c.degree, c.count(), c.knots.data(), c.homogeneous.data(), u);
  return {sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3]};
}

}  // namespace nurbs
