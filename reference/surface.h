// The data model every part reads: a NURBS surface stored once, in double precision, with
// Cartesian control points and separate weights (the homogeneous form is derived on demand).
#pragma once

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "reference/trim.h"

namespace nurbs {

using Point3 = std::array<double, 3>;

struct TSplineSurface;  // reference/tspline.h

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
  // The face this surface came from keeps only the part inside its trimming loops (absent: the
  // whole domain). Every strategy still evaluates the whole surface; the trim says which samples
  // count (reference/trim_classify.h).
  std::optional<Trim> trim;
  // The face is reversed relative to the surface (a CAD face's orientation): its outward normal
  // is -(S_u x S_v). The reference's normals and every strategy's, as the harness scores and
  // writes them, are flipped for such a surface (harness/metrics.h orient_normals).
  bool reversed = false;
  // A T-spline surface (001; reference/tspline.h) in its point-based form, instead of a tensor
  // net: then only `name` and the degrees above are set (count_u = count_v = 0, no knots, points
  // or weights, no trim), and the domain, control points and weights below come from it. A
  // strategy without Capabilities::tspline is refused such a surface before it sees it. Shared
  // and immutable, so copying a scene (a deforming frame, an isolated child) stays cheap.
  std::shared_ptr<const TSplineSurface> tspline;

  bool is_tspline() const { return tspline != nullptr; }
  // The control points and weights of either kind (NURBS: the net, row-major).
  const std::vector<Point3>& control_points() const;
  const std::vector<double>& control_weights() const;

  const Point3& point(int i, int j) const {
    return points[static_cast<std::size_t>(i) * count_v + j];
  }
  double weight(int i, int j) const { return weights[static_cast<std::size_t>(i) * count_v + j]; }
  bool is_rational() const;

  // Parameter domain: [knots[degree], knots[count]] in each direction for NURBS, the stored one
  // for a T-spline.
  double u_min() const;
  double u_max() const;
  double v_min() const;
  double v_max() const;
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
  bool has_trims() const;
};

}  // namespace nurbs
