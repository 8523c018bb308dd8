// The GPU's own device-to-device copy bandwidth, for the harness's limit-device-copy row
// (harness/copy_limit.h): timed on the Vulkan device the Vulkan strategies would use (the same
// --device), where Vulkan is built; this front keeps the harness free of any API's headers.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "strategies/strategy.h"

namespace nurbs {

struct DeviceCopyTiming {
  DeviceInfo device;              // the device that copied, as its strategies record it
  double setup_s = 0;             // device (first copy of a session), buffers, an untimed copy
  std::vector<double> seconds;    // one copy of all the bytes per repetition
  bool device_timestamps = true;  // false: host clock around submission and wait
};

// The copies of one run: the device is probed and opened once, on the first use, and kept with
// its buffers for the next copy; a copy that throws drops them, so the next opens a fresh device.
class DeviceCopy {
 public:
  explicit DeviceCopy(StrategyOptions options);
  ~DeviceCopy();
  DeviceCopy(const DeviceCopy&) = delete;
  DeviceCopy& operator=(const DeviceCopy&) = delete;

  // Whether there is a device to copy on: "not built with Vulkan", or the Vulkan probe's reason
  // (no loader, no driver, no device). Probed on the first call.
  const Availability& availability();

  // `repetitions` device-to-device copies of `bytes` (a multiple of 4, else
  // std::invalid_argument); see strategies/vulkan/vk_copy_bandwidth.h. Throws std::runtime_error
  // with the reason there is no such device, RefusedError when the buffers do not fit,
  // DeviceTimeout when the device does not answer.
  DeviceCopyTiming time(std::size_t bytes, int repetitions);

 private:
  struct Bench;
  StrategyOptions options_;
  std::optional<Availability> availability_;
  std::unique_ptr<Bench> bench_;
};

}  // namespace nurbs
