// gl-tspline: what it is, stated once for its entry in a build with OpenGL and its
// unavailable stub in a build without (strategies/registry.h, StrategyDescriptor).
#include "reference/validation.h"
#include "strategies/gl_tspline/gl_tspline.h"

namespace nurbs {

namespace {

constexpr const char* kSource =
    "001 §T-splines GPU evaluation (T-spline evaluation split into passes)";
Capabilities tspline_capabilities() {
  Capabilities c;
  // Every odd degree the data model allows: the shader's arrays are sized per compiled degree
  // pair (LB_MAX_DEGREE + 2 knots), so no fixed limit below kMaxDegree applies; degrees 1 to 7 are
  // tested.
  c.max_degree = kMaxDegree;
  c.rational = true;
  c.normals = true;
  c.fp32 = true;
  c.fp64 = false;                                // RGBA32F targets, as 001's textures
  c.sampling = SamplingModes{true, true, true};  // one fragment per sample, any (u, v) list
  c.tspline = true;
  c.tspline_only = true;
  c.updates_control_points = true;  // the points texture alone is re-uploaded  // its NURBS
                                    // counterpart is gl-pingpong (000 / 001's NURBS section)
  return c;
}

}  // namespace

StrategyDescriptor gl_tspline_descriptor() {
  return {"gl-tspline", kSource, "strategy", tspline_capabilities()};
}

}  // namespace nurbs
