// vk-bezier when the build has no Vulkan (no headers/loader, no glslang/spirv-val, or
// NURBSBENCH_CPU_ONLY): still registered, so `list` and results say why it did not run.
#include "strategies/vk_bezier/vk_bezier.h"

namespace nurbs {

StrategyEntry vk_bezier_entry() {
  return unavailable_entry(vk_bezier_descriptor(), NURBSBENCH_VULKAN_MISSING);
}

}  // namespace nurbs
