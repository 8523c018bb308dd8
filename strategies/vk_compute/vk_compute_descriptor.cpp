// vk-compute: what it is, stated once for its entry in a build with Vulkan and its
// unavailable stub in a build without (strategies/registry.h, StrategyDescriptor).
#include "reference/validation.h"
#include "strategies/vk_compute/vk_compute.h"

namespace nurbs {

namespace {

Capabilities compute_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  c.fp64 = true;  // where the device has shaderFloat64; prepare() refuses it elsewhere
  c.updates_control_points = true;
  c.trims = true;
  return c;
}

}  // namespace

StrategyDescriptor vk_compute_descriptor() {
  return {"vk-compute", std::string(kVkComputeSource), "strategy", compute_capabilities()};
}

}  // namespace nurbs
