#include "strategies/vulkan/vk_copy_bandwidth.h"

#include <fmt/format.h>

#include <chrono>
#include <cstdint>
#include <optional>
#include <stdexcept>

#include "strategies/vulkan/vk_device.h"

namespace nurbs::vulkan {

namespace {

template <typename F>
double seconds_of(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

DeviceCopyTiming time_buffer_copy(int device_index, VkDeviceSize bytes, int repetitions) {
  if (bytes == 0 || bytes % 4 != 0)
    throw std::invalid_argument(
        fmt::format("time_buffer_copy: {} bytes, not a multiple of 4", bytes));
  DeviceCopyTiming out;
  std::optional<Device> device;
  std::optional<Buffer> source, destination;
  std::optional<QueryPools> queries;
  const auto fill_source = [&](std::uint32_t word) {
    device->submit_and_wait(
        [&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, source->handle(), 0, VK_WHOLE_SIZE, word); });
  };
  const VkBufferCopy region{0, 0, bytes};
  const auto copy = [&](VkCommandBuffer cb) {
    vkCmdCopyBuffer(cb, source->handle(), destination->handle(), 1, &region);
  };
  out.setup_s = seconds_of([&] {
    device.emplace(device_index, Requirements{});
    source.emplace(*device, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, "the copy's source");
    destination.emplace(*device, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, "the copy's destination");
    queries.emplace(*device, 0);
    fill_source(0);
    device->submit_and_wait(copy);
  });
  out.device = device->record();
  out.device_timestamps = device->timestamp_valid_bits() > 0;
  std::uint32_t word = 0;
  for (int k = 0; k < repetitions; ++k) {
    // A word no earlier pass wrote, so the read-back below proves the last copy happened.
    word = 0x3f800000u + static_cast<std::uint32_t>(k) + 1;
    fill_source(word);
    const double host_s = seconds_of([&] {
      device->submit_and_wait([&](VkCommandBuffer cb) {
        queries->reset(cb);
        queries->begin(cb);
        copy(cb);
        queries->end(cb);
        memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
      });
    });
    out.seconds.push_back(queries->elapsed_s().value_or(host_s));
  }
  if (repetitions > 0)
    for (const VkDeviceSize at : {VkDeviceSize{0}, bytes / 8 * 4, bytes - 4}) {
      std::uint32_t got = 0;
      destination->read(&got, sizeof got, at);
      if (got != word)
        throw std::runtime_error(
            fmt::format("the device copy did not arrive: word at byte {} is {:#x}, expected {:#x}",
                        at, got, word));
    }
  return out;
}

}  // namespace nurbs::vulkan
