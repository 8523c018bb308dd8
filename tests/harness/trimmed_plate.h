// The harness tests' trimmed scene: a bilinear plate S(u, v) = (u, v, 0) over [0, 1]^2 whose face
// is the domain minus the square hole [0.3, 0.7]^2. Outer loop: the domain's boundary; inner loop:
// the hole; each edge one degree-1 trim curve. Which samples are inside, and how far each lies
// from the trim boundary, is known in closed form (hand_inside, hand_distance), so the tests check
// the harness -- and the classifier it runs -- against values computed without it.
#pragma once

#include <algorithm>
#include <cmath>

#include "reference/surface.h"

namespace nurbs::test {

inline constexpr double kHoleLo = 0.3, kHoleHi = 0.7;

inline TrimCurve trim_line(Point2 from, Point2 to) {
  return TrimCurve{1, {0, 0, 1, 1}, {from, to}, {1, 1}};
}

// The four sides of the axis-aligned square [lo, hi]^2, counter-clockwise.
inline TrimLoop square_loop(double lo, double hi) {
  return TrimLoop{{trim_line({lo, lo}, {hi, lo}), trim_line({hi, lo}, {hi, hi}),
                   trim_line({hi, hi}, {lo, hi}), trim_line({lo, hi}, {lo, lo})}};
}

inline Scene trimmed_plate() {
  Surface s;
  s.name = "plate";
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}};
  s.weights = {1, 1, 1, 1};
  Trim trim;
  trim.loops = {square_loop(0, 1), square_loop(kHoleLo, kHoleHi)};
  s.trim = trim;
  return Scene{"trimmed-test-plate", "a unit plate with a square hole", {s}};
}

// Inside the face: in the (closed) domain and not strictly inside the hole.
inline bool hand_inside(double u, double v) {
  const bool in_domain = u >= 0 && u <= 1 && v >= 0 && v <= 1;
  const bool in_hole = u > kHoleLo && u < kHoleHi && v > kHoleLo && v < kHoleHi;
  return in_domain && !in_hole;
}

// Distance in (u, v) to the nearest trim curve, for a (u, v) in the domain: to the domain's
// sides, or to the hole's boundary (from outside: to the nearest point of the square; from
// inside: to its nearest side).
inline double hand_distance(double u, double v) {
  const double to_domain = std::min({u, 1 - u, v, 1 - v});
  const double du = std::max({kHoleLo - u, 0.0, u - kHoleHi});
  const double dv = std::max({kHoleLo - v, 0.0, v - kHoleHi});
  const double to_hole = du > 0 || dv > 0
                             ? std::hypot(du, dv)
                             : std::min({u - kHoleLo, kHoleHi - u, v - kHoleLo, kHoleHi - v});
  return std::min(to_domain, to_hole);
}

}  // namespace nurbs::test
