// vk-ksquad: what it is, stated once for its entry in a build with Vulkan and its
// unavailable stub in a build without (strategies/registry.h, StrategyDescriptor).
#include "strategies/stair_basis/stair.h"
#include "strategies/vk_ksquad/vk_ksquad.h"

namespace nurbs {

namespace {

Capabilities ksquad_capabilities() {
  Capabilities c;
  // 15, the validation limit: no device limit depends on the degree (net and constants are
  // storage buffers, one control point per patch; push constants and levels do not grow with it).
  c.max_degree = kStairMaxDegree;
  c.normals = true;  // both modes: derivatives of the same stair basis (stair_derivative)
  c.fp64 = false;    // Vulkan tessellation stages in float; shaderFloat64 is optional
  c.sampling.explicit_list = false;  // not a tensor of runs
  // The tessellator chooses the samples in adaptive mode and for span grids (the float rounding
  // of the requested ones); a grid's are the requested ones.
  c.chooses_own_samples = true;
  c.updates_control_points = true;  // re-uploads only the control points (and corners)
  // Uniform mode: direct trimming of the requested samples in a compute pass (the shared
  // vulkan::TrimClassifier); render() discards outside fragments with the same GLSL.
  c.trims = true;
  return c;
}

}  // namespace

StrategyDescriptor vk_ksquad_descriptor() {
  return {"vk-ksquad", "003 §2-4 (RPNS 2014): KSQuads in Vulkan tessellation stages, stair basis",
          "strategy", ksquad_capabilities()};
}

}  // namespace nurbs
