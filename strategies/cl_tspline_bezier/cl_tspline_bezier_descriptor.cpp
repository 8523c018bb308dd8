// cl-tspline-bezier: what it is, stated once for its entry in a build with OpenCL and its
// unavailable stub in a build without (strategies/registry.h, StrategyDescriptor).
#include "reference/validation.h"
#include "strategies/cl_tspline_bezier/cl_tspline_bezier.h"

namespace nurbs {

namespace {

Capabilities tspline_bezier_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  c.tspline = true;
  c.tspline_only = true;            // its NURBS counterpart is cpu-bezier
  c.updates_control_points = true;  // control points and the decomposition only
  return c;
}

}  // namespace

StrategyDescriptor cl_tspline_bezier_descriptor() {
  return {"cl-tspline-bezier",
          "Scott et al. 2011 Bézier extraction of T-splines, evaluated as rational Bézier patches "
          "(the T-spline issue's extracted-Bézier path)",
          "strategy", tspline_bezier_capabilities()};
}

}  // namespace nurbs
