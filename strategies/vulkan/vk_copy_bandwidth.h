// The GPU's own device-to-device copy, the ceiling a compute strategy's output stream runs into on
// the device (issue 29: vk-compute "at 4096² within 2x of the GPU's own device-to-device copy
// bandwidth for the same output bytes"), as the host's store pass is the CPU strategies' ceiling
// (harness/store_limit.h). The harness turns it into the limit-device-copy row
// (harness/copy_limit.h); on lavapipe the copy is a host memcpy and the row is a CPU figure.
#pragma once

#include <vulkan/vulkan.h>

#include "strategies/device_copy.h"

namespace nurbs::vulkan {

// `repetitions` vkCmdCopyBuffer of `bytes` (a multiple of 4) between two buffers allocated as the
// strategies allocate their outputs (Buffer: device-local first), after one untimed copy that
// pays first touches. Before each copy the source is refilled with a new word (its own
// submission, so no timestamp covers it); after the last, words of the destination are read back
// and must be that word -- a copy that did not happen is an error, not a fast row. Throws
// std::runtime_error (no device, a failed call), MissingFeature, RefusedError (out of memory),
// DeviceTimeout (strategies/device_wait.h).
DeviceCopyTiming time_buffer_copy(int device_index, VkDeviceSize bytes, int repetitions);

}  // namespace nurbs::vulkan
