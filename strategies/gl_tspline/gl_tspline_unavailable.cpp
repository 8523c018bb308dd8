// gl-tspline when the build has no OpenGL (no OSMesa/EGL development packages, or
// NURBSBENCH_CPU_ONLY): still registered, so `list` and results say why it did not run.
#include "strategies/gl_tspline/gl_tspline.h"

namespace nurbs {

StrategyEntry gl_tspline_entry() {
  return {"gl-tspline",
          "001 §T-splines GPU evaluation (T-spline evaluation split into passes)",
          "strategy",
          [] {
            return Availability{false, NURBSBENCH_GL_MISSING};
          },
          [] {
            Capabilities c;
            c.tspline = c.tspline_only = true;
            return c;
          },
          [](const StrategyOptions&) -> std::unique_ptr<Strategy> {
            throw std::runtime_error(NURBSBENCH_GL_MISSING);
          }};
}

}  // namespace nurbs
