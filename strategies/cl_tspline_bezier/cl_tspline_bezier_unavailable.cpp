// cl-tspline-bezier when the build has no OpenCL (no headers/ICD loader, or NURBSBENCH_CPU_ONLY):
// still registered, so `list` and results say why it did not run.
#include <stdexcept>

#include "strategies/cl_tspline_bezier/cl_tspline_bezier.h"

namespace nurbs {

StrategyEntry cl_tspline_bezier_entry() {
  return {"cl-tspline-bezier",
          "Scott et al. 2011 Bézier extraction of T-splines, evaluated as rational Bézier patches "
          "(the T-spline issue's extracted-Bézier path)",
          "strategy",
          [] {
            return Availability{false, NURBSBENCH_OPENCL_MISSING};
          },
          [] {
            Capabilities c;
            c.tspline = c.tspline_only = true;
            return c;
          },
          [](const StrategyOptions&) -> std::unique_ptr<Strategy> {
            throw std::runtime_error(NURBSBENCH_OPENCL_MISSING);
          }};
}

}  // namespace nurbs
