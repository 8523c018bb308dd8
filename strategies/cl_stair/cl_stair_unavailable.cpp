// cl-stair when the build has no OpenCL (no headers/ICD loader, or NURBSBENCH_CPU_ONLY): still
// registered, so `list` and results say why it did not run.
#include "strategies/cl_stair/cl_stair.h"

namespace nurbs {

StrategyEntry cl_stair_entry() {
  return unavailable_entry(cl_stair_descriptor(), NURBSBENCH_OPENCL_MISSING);
}

}  // namespace nurbs
