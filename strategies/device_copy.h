// The GPU's own device-to-device copy bandwidth, for the harness's limit-device-copy row
// (harness/copy_limit.h): timed on the Vulkan device the Vulkan strategies would use (the same
// --device), where Vulkan is built; this front keeps the harness free of any API's headers.
#pragma once

#include <cstddef>
#include <vector>

#include "strategies/strategy.h"

namespace nurbs {

struct DeviceCopyTiming {
  DeviceInfo device;              // the device that copied, as its strategies record it
  double setup_s = 0;             // device, buffers and an untimed first copy
  std::vector<double> seconds;    // one copy of all the bytes per repetition
  bool device_timestamps = true;  // false: host clock around submission and wait
};

// Whether there is a device to copy on: "not built with Vulkan", or the Vulkan probe's reason (no
// loader, no driver, no device) for the device a run without --device picks.
Availability device_copy_availability(const StrategyOptions& options);

// `repetitions` device-to-device copies of `bytes` (a multiple of 4); see
// strategies/vulkan/vk_copy_bandwidth.h. Throws std::runtime_error with the reason there is no
// such device ("not built with Vulkan", no loader, no device), RefusedError when the buffers do not
// fit, DeviceTimeout when the device does not answer.
DeviceCopyTiming time_device_copy(const StrategyOptions& options, std::size_t bytes,
                                  int repetitions);

}  // namespace nurbs
