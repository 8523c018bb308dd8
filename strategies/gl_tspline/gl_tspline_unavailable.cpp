// gl-tspline when the build has no OpenGL (no OSMesa/EGL development packages, or
// NURBSBENCH_CPU_ONLY): still registered, so `list` and results say why it did not run.
#include "strategies/gl_tspline/gl_tspline.h"

namespace nurbs {

StrategyEntry gl_tspline_entry() {
  return unavailable_entry(gl_tspline_descriptor(), NURBSBENCH_GL_MISSING);
}

}  // namespace nurbs
