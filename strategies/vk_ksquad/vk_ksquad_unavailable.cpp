// vk-ksquad when the build has no Vulkan (no headers/loader, no glslang/spirv-val, or
// NURBSBENCH_CPU_ONLY): still registered, so `list` and results say why it did not run.
#include <stdexcept>

#include "strategies/vk_ksquad/vk_ksquad.h"

namespace nurbs {

StrategyEntry vk_ksquad_entry() {
  return {"vk-ksquad",
          "003 §2-4 (RPNS 2014): KSQuads in Vulkan tessellation stages, stair basis",
          "strategy",
          [] {
            return Availability{false, NURBSBENCH_VULKAN_MISSING};
          },
          [] { return Capabilities{}; },
          [](const StrategyOptions&) -> std::unique_ptr<Strategy> {
            throw std::runtime_error(NURBSBENCH_VULKAN_MISSING);
          }};
}

}  // namespace nurbs
