#include "scenes/deforming.h"

#include <cmath>
#include <memory>
#include <numbers>

#include "reference/tspline.h"

namespace nurbs {

void deform_scene(const Scene& base, int frame, Scene& out) {
  out.name = base.name;
  out.description = base.description;
  out.surfaces.resize(base.surfaces.size());
  const double diagonal = base.bounding_box_diagonal();
  const double amplitude = diagonal / 50, wavelength = diagonal / 2;
  const double phase = 2 * std::numbers::pi * frame / kDeformingFramesPerPeriod;
  for (std::size_t i = 0; i < base.surfaces.size(); ++i) {
    const Surface& from = base.surfaces[i];
    Surface& to = out.surfaces[i];
    // Copy-assignments reuse `to`'s storage when it already has base's sizes.
    to.name = from.name;
    to.degree_u = from.degree_u;
    to.degree_v = from.degree_v;
    to.count_u = from.count_u;
    to.count_v = from.count_v;
    to.knots_u = from.knots_u;
    to.knots_v = from.knots_v;
    to.weights = from.weights;
    // The face stays the face: only control points move, the trim (in (u, v)) and orientation are
    // the base scene's.
    to.trim = from.trim;
    to.reversed = from.reversed;
    const auto move = [&](const std::vector<Point3>& points, std::vector<Point3>& moved) {
      moved.resize(points.size());
      for (std::size_t k = 0; k < points.size(); ++k) {
        const Point3& p = points[k];
        moved[k] = p;
        moved[k][2] +=
            amplitude * std::sin(2 * std::numbers::pi * (p[0] + p[1]) / wavelength + phase);
      }
    };
    move(from.points, to.points);
    // A T-spline is shared and immutable: a frame gets its own copy (local knots and weights
    // unchanged), allocated per frame.
    to.tspline = from.tspline;
    if (from.tspline) {
      auto moved = std::make_shared<TSplineSurface>(*from.tspline);
      move(from.tspline->points, moved->points);
      to.tspline = std::move(moved);
    }
  }
}

Scene deformed_scene(const Scene& base, int frame) {
  Scene out = base;
  deform_scene(base, frame, out);
  return out;
}

}  // namespace nurbs
