#include "strategies/vulkan/vk_copy_bandwidth.h"

#include <fmt/format.h>

#include <cstdint>
#include <stdexcept>

#include "strategies/wall_clock.h"

namespace nurbs::vulkan {

CopyBench::CopyBench(int device_index) {
  device_setup_s_ = wall_seconds([&] {
    device_.emplace(device_index, Requirements{});
    queries_.emplace(*device_, 0);
  });
}

DeviceCopyTiming CopyBench::time(VkDeviceSize bytes, int repetitions) {
  if (bytes == 0 || bytes % 4 != 0)
    throw std::invalid_argument(fmt::format("device copy: {} bytes, not a multiple of 4", bytes));
  DeviceCopyTiming out;
  const auto fill_source = [&](std::uint32_t word) {
    device_->submit_and_wait(
        [&](VkCommandBuffer cb) { vkCmdFillBuffer(cb, source_->handle(), 0, bytes, word); });
  };
  const VkBufferCopy region{0, 0, bytes};
  const auto copy = [&](VkCommandBuffer cb) {
    vkCmdCopyBuffer(cb, source_->handle(), destination_->handle(), 1, &region);
  };
  out.setup_s =
      device_setup_s_ + wall_seconds([&] {
        if (bytes > capacity_) {
          capacity_ = 0;
          source_.reset();
          destination_.reset();
          source_.emplace(*device_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, "the copy's source");
          destination_.emplace(*device_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               "the copy's destination");
          capacity_ = bytes;
        }
        fill_source(0);
        device_->submit_and_wait(copy);
      });
  device_setup_s_ = 0;
  out.device = device_->record();
  out.device_timestamps = device_->timestamp_valid_bits() > 0;
  std::uint32_t word = 0;
  for (int k = 0; k < repetitions; ++k) {
    // A word no earlier pass wrote, so the read-back below proves the last copy happened.
    word = 0x3f800000u + static_cast<std::uint32_t>(k) + 1;
    fill_source(word);
    const double host_s = wall_seconds([&] {
      device_->submit_and_wait([&](VkCommandBuffer cb) {
        queries_->reset(cb);
        queries_->begin(cb);
        copy(cb);
        queries_->end(cb);
        memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
      });
    });
    out.seconds.push_back(queries_->elapsed_s().value_or(host_s));
  }
  if (repetitions > 0)
    for (const VkDeviceSize at : {VkDeviceSize{0}, bytes / 8 * 4, bytes - 4}) {
      std::uint32_t got = 0;
      destination_->read(&got, sizeof got, at);
      if (got != word)
        throw std::runtime_error(
            fmt::format("the device copy did not arrive: word at byte {} is {:#x}, expected {:#x}",
                        at, got, word));
    }
  return out;
}

}  // namespace nurbs::vulkan
