#include "strategies/device_copy.h"

#include <stdexcept>

#if NURBSBENCH_DEVICE_COPY_VULKAN
#include "strategies/vulkan/vk_copy_bandwidth.h"
#include "strategies/vulkan/vk_device.h"
#endif

namespace nurbs {

Availability device_copy_availability(const StrategyOptions& options) {
#if NURBSBENCH_DEVICE_COPY_VULKAN
  (void)options;  // a --device out of range is the copy's error, as it is a strategy's
  return vulkan::probe(vulkan::Requirements{});
#else
  (void)options;
  return {false, "not built with Vulkan"};
#endif
}

DeviceCopyTiming time_device_copy(const StrategyOptions& options, std::size_t bytes,
                                  int repetitions) {
#if NURBSBENCH_DEVICE_COPY_VULKAN
  return vulkan::time_buffer_copy(vulkan::device_option(options), bytes, repetitions);
#else
  (void)options, (void)bytes, (void)repetitions;
  throw std::runtime_error("not built with Vulkan");
#endif
}

}  // namespace nurbs
