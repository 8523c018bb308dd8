// A trimmed test scene whose trim curves have any degree, for the limits of the trimming paths
// (direct trimming up to kMaxDegree, GLU up to 7).
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "reference/surface.h"

namespace nurbs::test {

// A bilinear unit plate trimmed by one loop of two rational curves of `degree` (clamped, four
// spans each, so several Bézier pieces per curve): a wavy upper arc from (0.8, 0.5) to
// (0.2, 0.5) and a wavy lower arc back, radii alternating 0.3 +- 0.1 about (0.5, 0.5), weights
// between 0.5 and 2. Exercises every trim degree up to kMaxDegree (direct trimming refused
// degrees above 8 before its extrema were isolated at degree 2n - 1 <= 29; GLU's trim tessellator
// reads past its tables above degree 7).
inline Scene high_degree_trim_scene(int degree) {
  Surface s;
  s.name = fmt::format("plate-trim-degree-{}", degree);
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0.1}, {1, 1, 0}};
  s.weights = {1, 1, 1, 1};
  Trim trim;
  TrimLoop& loop = trim.loops.emplace_back();
  const int count = degree + 4;
  for (int arc = 0; arc < 2; ++arc) {
    TrimCurve& c = loop.curves.emplace_back();
    c.degree = degree;
    c.knots.assign(static_cast<std::size_t>(degree) + 1, 0.0);
    for (int k = 1; k < count - degree; ++k)
      c.knots.push_back(static_cast<double>(k) / (count - degree));
    c.knots.insert(c.knots.end(), static_cast<std::size_t>(degree) + 1, 1.0);
    for (int i = 0; i < count; ++i) {
      const double angle = std::numbers::pi * (arc + static_cast<double>(i) / (count - 1));
      const bool end = i == 0 || i == count - 1;
      const double r = end ? 0.3 : 0.3 + (i % 2 ? 0.1 : -0.1);
      // The ends exactly on the axis, so the two arcs meet without a gap.
      const double y = end ? 0.5 : 0.5 + r * std::sin(angle);
      const double x =
          end ? 0.5 + ((i == 0) == (arc == 0) ? 0.3 : -0.3) : 0.5 + r * std::cos(angle);
      c.points.push_back({x, y});
      c.weights.push_back(0.5 + 1.5 * ((i * 5 + arc) % 7) / 6.0);
    }
  }
  s.trim = trim;
  Scene scene;
  scene.surfaces.push_back(std::move(s));
  return scene;
}

}  // namespace nurbs::test
