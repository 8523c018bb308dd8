// The built-in `trimmed-plate` scene: a bicubic plate over the (u, v) domain [0, 1]^2 keeping the
// part inside a rounded rectangle (lines and rational quadratic quarter circles) and outside a
// circular hole (one rational quadratic NURBS circle), so the inside area is known in closed form
// and exact circles test that the classification follows the curves, not their control polygons.
#pragma once

#include "reference/surface.h"

namespace nurbs {

struct TrimmedPlateShape {
  double low = 0.05, high = 0.95;  // the rounded rectangle [low, high]^2
  double corner_radius = 0.15;
  double hole_center_u = 0.5, hole_center_v = 0.5, hole_radius = 0.2;

  // Inside area in (u, v) (the domain has area 1): the rectangle less its four corners' excess
  // over the quarter circles, less the hole.
  double inside_area() const;
};

Scene trimmed_plate_scene(const TrimmedPlateShape& shape = {});

// The plate's two loops (rounded rectangle, then the hole) mapped from [0, 1]^2 onto the domain
// [u0, u1] x [v0, v1] of another surface. The map is affine, so the curves stay exact rational
// curves (circles become ellipses when the domain is not square) and the inside area scales by
// (u1 - u0)(v1 - v0).
Trim trimmed_plate_trim(const TrimmedPlateShape& shape, double u0, double u1, double v0, double v1);

}  // namespace nurbs
