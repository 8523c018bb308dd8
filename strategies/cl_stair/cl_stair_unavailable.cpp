// cl-stair when the build has no OpenCL (no headers/ICD loader, or NURBSBENCH_CPU_ONLY): still
// registered, so `list` and results say why it did not run.
#include <stdexcept>

#include "strategies/cl_stair/cl_stair.h"

namespace nurbs {

StrategyEntry cl_stair_entry() {
  return {"cl-stair",
          "003 §3.2 (RPNS 2014): non-recursive stair basis, one work-group per KSQuad",
          "strategy",
          [] {
            return Availability{false, NURBSBENCH_OPENCL_MISSING};
          },
          [] { return Capabilities{}; },
          [](const StrategyOptions&) -> std::unique_ptr<Strategy> {
            throw std::runtime_error(NURBSBENCH_OPENCL_MISSING);
          }};
}

}  // namespace nurbs
