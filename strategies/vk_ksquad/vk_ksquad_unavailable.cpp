// vk-ksquad when the build has no Vulkan (no headers/loader, no glslang/spirv-val, or
// NURBSBENCH_CPU_ONLY): still registered, so `list` and results say why it did not run.
#include "strategies/vk_ksquad/vk_ksquad.h"

namespace nurbs {

StrategyEntry vk_ksquad_entry() {
  return unavailable_entry(vk_ksquad_descriptor(), NURBSBENCH_VULKAN_MISSING);
}

}  // namespace nurbs
