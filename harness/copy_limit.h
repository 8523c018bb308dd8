// The GPU's own ceiling for a result, measured in the same run as the strategies (issue 29:
// vk-compute "at 4096² within 2x of the GPU's own device-to-device copy bandwidth for the same
// output bytes ... as a limit- row, as the store-bandwidth row does on the CPU"). The row
// limit-device-copy times a device-to-device copy (vkCmdCopyBuffer, device timestamps) on the
// Vulkan device the Vulkan strategies use, of as many bytes as store_pass_bytes() gives the host's
// store pass: the request's output, at least 64 MiB, more than a GPU's last-level cache (50 MiB on
// an H100), so the copy pays memory, not cache. Its points/s are the points a strategy on that
// device would reach if writing its output at the copy's speed were all it did. A copy reads as
// many bytes as it writes: the row holds a strategy to a stream that moves twice its output, the
// ceiling the issue names, not to a store-only stream (no API offers a GPU store benchmark).
// On lavapipe the device is the host and the copy a memcpy: a CPU figure, labelled
// so by its device. Unavailable, with the reason, where there is no Vulkan device.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

#include "harness/record.h"
#include "reference/surface.h"
#include "strategies/device_copy.h"
#include "strategies/strategy.h"

namespace nurbs {

inline constexpr std::string_view kDeviceCopyLimitName = "limit-device-copy";

// The limit-device-copy row for `scene` and `request` on `device_copy`'s device (the run's
// --device, opened once for all its rows): `repetitions` timed copies after an untimed one.
// figures: bytes_per_point, pass_bytes, copy_bytes_per_s (bytes written per second). Never throws
// for the device's sake: a missing device is unavailable, a refused allocation refused, a hang
// timed_out, a wrong copy failed.
Record measure_device_copy_limit(const Scene& scene, const EvalRequest& request, int repetitions,
                                 DeviceCopy& device_copy);

// `r`'s points/s over the limit-device-copy row for the same scene, samples and precision, when
// `r` ran on the device that copied (same device name); none otherwise or when the copy wrote
// under kStoreLimitMinBytes.
std::optional<double> fraction_of_device_copy_limit(const Record& r,
                                                    const std::vector<Record>& records);

}  // namespace nurbs
