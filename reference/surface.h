// The data model every part reads: a NURBS surface stored once, in double precision, with
// Cartesian control points and separate weights (the homogeneous form is derived on demand).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace nurbs {

using Point3 = std::array<double, 3>;

struct Surface {
  std::string name;
  int degree_u = 0;
  int degree_v = 0;
  int count_u = 0;  // control points along u
  int count_v = 0;  // control points along v
  std::vector<double> knots_u;
  std::vector<double> knots_v;
  std::vector<Point3> points;   // point (i, j) at i*count_v + j, NOT pre-multiplied by the weight
  std::vector<double> weights;  // same order; all 1 for a non-rational surface

  const Point3& point(int i, int j) const {
    return points[static_cast<std::size_t>(i) * count_v + j];
  }
  double weight(int i, int j) const { return weights[static_cast<std::size_t>(i) * count_v + j]; }
  bool is_rational() const;

  // Parameter domain [knots[degree], knots[count]] in each direction.
  double u_min() const { return knots_u[degree_u]; }
  double u_max() const { return knots_u[count_u]; }
  double v_min() const { return knots_v[degree_v]; }
  double v_max() const { return knots_v[count_v]; }
};

struct Scene {
  std::string name;
  std::string description;
  std::vector<Surface> surfaces;

  // Largest |coordinate| over all control points: the scale float32 ulps are measured against.
  double largest_coordinate() const;
  // Diagonal of the control points' bounding box: the scale of max_rel.
  double bounding_box_diagonal() const;
  std::size_t control_point_count() const;
};

}  // namespace nurbs
