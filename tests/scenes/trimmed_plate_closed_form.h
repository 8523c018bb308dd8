// The built-in trimmed-plate's face in closed form (scenes/trimmed_plate.h): tests compare a
// classification with it instead of with the classifier that produced it.
#pragma once

#include <algorithm>
#include <cmath>

#include "scenes/trimmed_plate.h"

namespace nurbs::test {

// Signed distance in (u, v) to the face's boundary, negative inside: the rounded rectangle's
// (a rounded box's SDF) against the hole's circle.
inline double trimmed_plate_signed_distance(const TrimmedPlateShape& s, double u, double v) {
  const double centre = (s.low + s.high) / 2, half = (s.high - s.low) / 2 - s.corner_radius;
  const double qu = std::abs(u - centre) - half, qv = std::abs(v - centre) - half;
  const double box = std::hypot(std::max(qu, 0.0), std::max(qv, 0.0)) +
                     std::min(std::max(qu, qv), 0.0) - s.corner_radius;
  const double hole = s.hole_radius - std::hypot(u - s.hole_center_u, v - s.hole_center_v);
  return std::max(box, hole);
}

}  // namespace nurbs::test
