// vk-compute when the build has no Vulkan (no headers/loader, no glslang/spirv-val, or
// NURBSBENCH_CPU_ONLY): still registered, so `list` and results say why it did not run.
#include <stdexcept>

#include "strategies/vk_compute/vk_compute.h"

namespace nurbs {

StrategyEntry vk_compute_entry() {
  return {"vk-compute",
          std::string(kVkComputeSource),
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
