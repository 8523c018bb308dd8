#include "harness/copy_limit.h"

#include <fmt/format.h>

#include "harness/store_limit.h"
#include "strategies/device_copy.h"

namespace nurbs {

Record measure_device_copy_limit(const Scene& scene, const EvalRequest& request, int repetitions,
                                 DeviceCopy& device_copy) {
  Record r = limit_record(kDeviceCopyLimitName, scene, request, repetitions);
  const std::size_t bytes_per_point = result_bytes_per_point(request);
  const std::size_t bytes = store_pass_bytes(r.points * bytes_per_point);
  measure_on_device(r, device_copy.availability(), [&] {
    DeviceCopyTiming copy = device_copy.time(bytes, repetitions);
    r.device = std::move(copy.device);
    r.device.details["kernel"] =
        "vkCmdCopyBuffer between two output-like buffers, at least 64 MiB (reads and writes the "
        "bytes)";
    r.device.details["clock"] =
        copy.device_timestamps ? "device timestamps" : "host clock around submission and wait";
    r.setup_s = copy.setup_s;
    set_limit_seconds(r, std::move(copy.seconds), bytes, bytes_per_point);
    r.figures["copy_bytes_per_s"] = r.throughput_pts_per_s * static_cast<double>(bytes_per_point);
  });
  return r;
}

std::optional<double> fraction_of_device_copy_limit(const Record& r,
                                                    const std::vector<Record>& records) {
  const Record* limit = limit_row_on_device(r, records, kDeviceCopyLimitName);
  if (!limit || limit_too_small(*limit)) return std::nullopt;
  return r.throughput_pts_per_s / limit->throughput_pts_per_s;
}

}  // namespace nurbs
