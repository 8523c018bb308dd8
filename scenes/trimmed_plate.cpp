#include "scenes/trimmed_plate.h"

#include <cmath>
#include <numbers>

namespace nurbs {

double TrimmedPlateShape::inside_area() const {
  const double side = high - low, r = corner_radius;
  return side * side - (4.0 - std::numbers::pi) * r * r -
         std::numbers::pi * hole_radius * hole_radius;
}

namespace {

TrimCurve line(Point2 a, Point2 b) {
  return {1, {0, 0, 1, 1}, {a, b}, {1, 1}};
}

// A quarter circle from a to b whose tangents meet at `corner`: rational quadratic, middle
// weight cos(45°) (The NURBS Book §7.3).
TrimCurve quarter_arc(Point2 a, Point2 corner, Point2 b) {
  return {2, {0, 0, 0, 1, 1, 1}, {a, corner, b}, {1, std::numbers::sqrt2 / 2, 1}};
}

// The full circle as one degree-2 NURBS curve on the circumscribed square's 9 points
// (The NURBS Book Ex. 7.2's knots {0,0,0,1/4,1/4,1/2,1/2,3/4,3/4,1,1,1}).
TrimCurve circle(double cu, double cv, double r) {
  const double w = std::numbers::sqrt2 / 2;
  return {2,
          {0, 0, 0, 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1, 1, 1},
          {{cu + r, cv},
           {cu + r, cv + r},
           {cu, cv + r},
           {cu - r, cv + r},
           {cu - r, cv},
           {cu - r, cv - r},
           {cu, cv - r},
           {cu + r, cv - r},
           {cu + r, cv}},
          {1, w, 1, w, 1, w, 1, w, 1}};
}

}  // namespace

Scene trimmed_plate_scene(const TrimmedPlateShape& shape) {
  Surface plate;
  plate.name = "plate";
  plate.degree_u = plate.degree_v = 3;
  plate.count_u = plate.count_v = 6;
  plate.knots_u = plate.knots_v = {0, 0, 0, 0, 1.0 / 3, 2.0 / 3, 1, 1, 1, 1};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j)
      plate.points.push_back({2.0 * i, 2.0 * j, 0.6 * std::sin(0.9 * i) * std::cos(0.7 * j)});
  plate.weights.assign(plate.points.size(), 1.0);

  plate.trim = trimmed_plate_trim(shape, 0, 1, 0, 1);

  Scene scene;
  scene.name = "trimmed-plate";
  scene.description =
      "bicubic plate trimmed to a rounded rectangle (lines + rational quarter circles) with a "
      "circular hole (rational quadratic): inside area known in closed form";
  scene.surfaces.push_back(std::move(plate));
  return scene;
}

Trim trimmed_plate_trim(const TrimmedPlateShape& shape, double u0, double u1, double v0,
                        double v1) {
  const double lo = shape.low, hi = shape.high, r = shape.corner_radius;
  TrimLoop outer;
  outer.curves = {
      line({lo + r, lo}, {hi - r, lo}), quarter_arc({hi - r, lo}, {hi, lo}, {hi, lo + r}),
      line({hi, lo + r}, {hi, hi - r}), quarter_arc({hi, hi - r}, {hi, hi}, {hi - r, hi}),
      line({hi - r, hi}, {lo + r, hi}), quarter_arc({lo + r, hi}, {lo, hi}, {lo, hi - r}),
      line({lo, hi - r}, {lo, lo + r}), quarter_arc({lo, lo + r}, {lo, lo}, {lo + r, lo})};
  TrimLoop hole;
  hole.curves = {circle(shape.hole_center_u, shape.hole_center_v, shape.hole_radius)};
  Trim trim;
  trim.loops = {outer, hole};
  // Built on [0, 1]^2, where the shape is given; the identity map leaves it bit for bit.
  for (TrimLoop& loop : trim.loops)
    for (TrimCurve& curve : loop.curves)
      for (Point2& p : curve.points) p = {u0 + (u1 - u0) * p[0], v0 + (v1 - v0) * p[1]};
  return trim;
}

}  // namespace nurbs
