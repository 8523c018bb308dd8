// A NURBS curve in 3D, control points in homogeneous form (w x, w y, w z, w): the input of 000 §2
// (curve evaluation), which the project otherwise meets only as 2D trimming curves
// (reference/trim.h, lifted to this form by setting z = 0).
#pragma once

#include <string_view>
#include <vector>

#include "reference/nurbs_math.h"

namespace nurbs {

struct Curve {
  int degree = 0;
  std::vector<double> knots;              // count + degree + 1, as a surface direction's
  std::vector<Vec4<double>> homogeneous;  // (w x, w y, w z, w), w > 0

  int count() const { return static_cast<int>(homogeneous.size()); }
  // The parameter domain [knots[degree], knots[count]].
  double start() const { return knots[static_cast<std::size_t>(degree)]; }
  double end() const { return knots[homogeneous.size()]; }
};

// The structural rules of a surface direction (docs/design.md §Data model: degree 1..15, knot
// count, order, multiplicities, non-empty domain), finite coordinates and weights > 0. Throws
// ValidationError (an InputError) naming `origin`, the field, the index and the value.
void validate_curve(const Curve& curve, std::string_view origin);

// A4.1 in double, divided by w: what the GPU curve path is compared with.
Vec3<double> curve_point(const Curve& curve, double u);

}  // namespace nurbs
