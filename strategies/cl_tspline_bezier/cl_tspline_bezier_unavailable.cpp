// cl-tspline-bezier when the build has no OpenCL (no headers/ICD loader, or NURBSBENCH_CPU_ONLY):
// still registered, so `list` and results say why it did not run.
#include "strategies/cl_tspline_bezier/cl_tspline_bezier.h"

namespace nurbs {

StrategyEntry cl_tspline_bezier_entry() {
  return unavailable_entry(cl_tspline_bezier_descriptor(), NURBSBENCH_OPENCL_MISSING);
}

}  // namespace nurbs
