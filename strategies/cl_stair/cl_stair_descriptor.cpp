// cl-stair: what it is, stated once for its entry in a build with OpenCL and its
// unavailable stub in a build without (strategies/registry.h, StrategyDescriptor).
#include "strategies/cl_stair/cl_stair.h"
#include "strategies/stair_basis/stair.h"

namespace nurbs {

namespace {

Capabilities stair_capabilities() {
  Capabilities c;
  c.max_degree = kStairMaxDegree;
  c.normals = false;  // positions only, as the paper's pipeline
  c.sampling.explicit_list = false;
  c.trims = true;  // classify(): direct trimming, strategies/trim_direct/ (classify.cl)
  c.updates_control_points = true;  // re-sends only the control points (003 §5)
  return c;
}

}  // namespace

StrategyDescriptor cl_stair_descriptor() {
  return {"cl-stair",
          "003 §3.2 (RPNS 2014): non-recursive stair basis, one work-group per tile of a KSQuad",
          "strategy", stair_capabilities()};
}

}  // namespace nurbs
