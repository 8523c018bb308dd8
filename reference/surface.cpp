#include "reference/surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/tspline.h"

namespace nurbs {

bool Surface::is_rational() const {
  const std::vector<double>& w = control_weights();
  return std::any_of(w.begin(), w.end(), [](double x) { return x != 1.0; });
}

const std::vector<Point3>& Surface::control_points() const {
  return tspline ? tspline->points : points;
}
const std::vector<double>& Surface::control_weights() const {
  return tspline ? tspline->weights : weights;
}

double Surface::u_min() const {
  return tspline ? tspline->u_min : knots_u[degree_u];
}
double Surface::u_max() const {
  return tspline ? tspline->u_max : knots_u[count_u];
}
double Surface::v_min() const {
  return tspline ? tspline->v_min : knots_v[degree_v];
}
double Surface::v_max() const {
  return tspline ? tspline->v_max : knots_v[count_v];
}

bool Scene::has_trims() const {
  return std::any_of(surfaces.begin(), surfaces.end(),
                     [](const Surface& s) { return s.trim.has_value(); });
}

double Scene::largest_coordinate() const {
  double largest = 0;
  for (const Surface& s : surfaces)
    for (const Point3& p : s.control_points())
      for (double c : p) largest = std::max(largest, std::fabs(c));
  return largest;
}

double Scene::bounding_box_diagonal() const {
  Point3 lo{}, hi{};
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const Surface& s : surfaces)
    for (const Point3& p : s.control_points())
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], p[c]);
        hi[c] = std::max(hi[c], p[c]);
      }
  if (!(lo[0] <= hi[0])) return 0;
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

std::size_t Scene::control_point_count() const {
  std::size_t n = 0;
  for (const Surface& s : surfaces) n += s.control_points().size();
  return n;
}

}  // namespace nurbs
