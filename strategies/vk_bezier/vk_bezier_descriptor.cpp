// vk-bezier: what it is, stated once for its entry in a build with Vulkan and its
// unavailable stub in a build without (strategies/registry.h, StrategyDescriptor).
#include "reference/validation.h"
#include "strategies/vk_bezier/vk_bezier.h"

namespace nurbs {

namespace {

Capabilities bezier_capabilities() {
  Capabilities c;
  // bezier.tese's BEZIER_MAX_ORDER; the points are a storage buffer and one vertex is a patch, so
  // no device limit grows with the degree.
  c.max_degree = kMaxDegree;
  c.normals = true;  // Bernstein derivatives of the same triangle (bezier.tese)
  c.fp64 = false;    // Vulkan tessellation stages in float; shaderFloat64 is optional
  c.sampling.explicit_list = false;  // the tessellator's lattices are tensors of runs
  c.chooses_own_samples = true;      // span grid: the tessellator's (a grid's: the requested)
  c.updates_control_points = true;   // the whole decomposition + upload (update_control_points)
  return c;
}

}  // namespace

StrategyDescriptor vk_bezier_descriptor() {
  return {"vk-bezier", std::string(kVkBezierSource), "baseline", bezier_capabilities()};
}

}  // namespace nurbs
