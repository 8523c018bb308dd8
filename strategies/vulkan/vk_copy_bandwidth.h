// The GPU's own device-to-device copy, the ceiling a compute strategy's output stream runs into on
// the device (issue 29: vk-compute "at 4096² within 2x of the GPU's own device-to-device copy
// bandwidth for the same output bytes"), as the host's store pass is the CPU strategies' ceiling
// (harness/store_limit.h). The harness turns it into the limit-device-copy row
// (harness/copy_limit.h); on lavapipe the copy is a host memcpy and the row is a CPU figure.
#pragma once

#include <vulkan/vulkan.h>

#include <optional>

#include "strategies/device_copy.h"
#include "strategies/vulkan/vk_device.h"

namespace nurbs::vulkan {

// One device and two buffers kept for a run's copies: a run times one copy per scene and sampling,
// nearly all of the same size (store_pass_bytes' floor), and opening the device and touching the
// buffers' pages each time would cost more than the copies.
class CopyBench {
 public:
  // Throws std::runtime_error (no device), MissingFeature.
  explicit CopyBench(int device_index);

  // `repetitions` vkCmdCopyBuffer of `bytes` (a multiple of 4, else std::invalid_argument)
  // between two buffers allocated as the strategies allocate their outputs (Buffer: device-local
  // first), after one untimed copy that pays first touches. Before each copy the source is
  // refilled with a new word (its own submission, so no timestamp covers it); after the last,
  // words of the destination are read back and must be that word -- a copy that did not happen is
  // an error, not a fast row. setup_s: the device (first call only), buffers grown to `bytes`
  // where they are smaller, and the untimed copy. Throws std::runtime_error (a failed call),
  // RefusedError (out of memory), DeviceTimeout (strategies/device_wait.h).
  DeviceCopyTiming time(VkDeviceSize bytes, int repetitions);

 private:
  double device_setup_s_ = 0;  // reported with the first timing
  std::optional<Device> device_;
  std::optional<QueryPools> queries_;
  std::optional<Buffer> source_, destination_;
  VkDeviceSize capacity_ = 0;
};

}  // namespace nurbs::vulkan
