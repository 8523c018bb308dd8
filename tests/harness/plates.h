// Plates for the harness tests: a bilinear patch from its four corners, and the trimmed plate --
// S(u, v) = (u, v, 0) over [0, 1]^2 whose face is the square [1/16, 15/16]^2 (outer loop) minus
// the square hole [0.3, 0.7]^2 (inner loop), each side one degree-1 trim curve. No sample of the
// tests' grids (u, v = k/8) lies on a trim curve, so every sample's classification is
// unambiguous, and it and the distance to the trim boundary are known in closed form
// (hand_inside, hand_distance): the tests check the harness -- and the classifier it runs --
// against values computed without either.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "reference/surface.h"

namespace nurbs::test {

inline constexpr double kOuterLo = 1.0 / 16, kOuterHi = 15.0 / 16;
inline constexpr double kHoleLo = 0.3, kHoleHi = 0.7;

inline TrimCurve trim_line(Point2 from, Point2 to) {
  return TrimCurve{1, {0, 0, 1, 1}, {from, to}, {1, 1}};
}

// The four sides of the axis-aligned square [lo, hi]^2, counter-clockwise.
inline TrimLoop square_loop(double lo, double hi) {
  return TrimLoop{{trim_line({lo, lo}, {hi, lo}), trim_line({hi, lo}, {hi, hi}),
                   trim_line({hi, hi}, {lo, hi}), trim_line({lo, hi}, {lo, lo})}};
}

// Degree 1 both ways over [0, 1]^2: S(0, 0) = p00, S(0, 1) = p01, S(1, 0) = p10, S(1, 1) = p11.
inline Surface bilinear_patch(std::string name, Point3 p00, Point3 p01, Point3 p10, Point3 p11) {
  Surface s;
  s.name = std::move(name);
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points = {p00, p01, p10, p11};
  s.weights = {1, 1, 1, 1};
  return s;
}

inline Scene trimmed_plate() {
  Surface s = bilinear_patch("plate", {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0});
  Trim trim;
  trim.loops = {square_loop(kOuterLo, kOuterHi), square_loop(kHoleLo, kHoleHi)};
  s.trim = trim;
  return Scene{"trimmed-test-plate", "a unit plate trimmed to a square frame", {s}};
}

inline bool in_square(double u, double v, double lo, double hi) {
  return u > lo && u < hi && v > lo && v < hi;
}

inline bool hand_inside(double u, double v) {
  return in_square(u, v, kOuterLo, kOuterHi) && !in_square(u, v, kHoleLo, kHoleHi);
}

// Distance from (u, v) to the boundary of the square [lo, hi]^2: to its nearest point from
// outside, to its nearest side from inside.
inline double square_distance(double u, double v, double lo, double hi) {
  const double du = std::max({lo - u, 0.0, u - hi}), dv = std::max({lo - v, 0.0, v - hi});
  if (du > 0 || dv > 0) return std::hypot(du, dv);
  return std::min({u - lo, hi - u, v - lo, hi - v});
}

inline double hand_distance(double u, double v) {
  return std::min(square_distance(u, v, kOuterLo, kOuterHi),
                  square_distance(u, v, kHoleLo, kHoleHi));
}

}  // namespace nurbs::test
