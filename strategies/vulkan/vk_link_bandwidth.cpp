// The Vulkan row of the host<->device link (strategies/link_copy.h): vkCmdCopyBuffer between a
// host-visible, host-cached buffer (what Device::staging gives the strategies) and a buffer
// allocated as the strategies allocate their outputs (device-local first), both kept for the run.
#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>

#include "strategies/link_copy.h"
#include "strategies/vulkan/vk_device.h"
#include "strategies/wall_clock.h"

namespace nurbs::vulkan {

namespace {

class LinkBench final : public LinkCopy::Bench {
 public:
  explicit LinkBench(int device_index) {
    device_setup_s_ = wall_seconds([&] { device_.emplace(device_index, Requirements{}); });
  }

  LinkTiming time(std::size_t bytes, int repetitions) override {
    LinkTiming out;
    const VkBufferCopy region{0, 0, bytes};
    const auto upload = [&] {
      device_->submit_and_wait([&](VkCommandBuffer cb) {
        vkCmdCopyBuffer(cb, host_->handle(), on_device_->handle(), 1, &region);
      });
    };
    const auto read_back = [&] {
      device_->submit_and_wait([&](VkCommandBuffer cb) {
        vkCmdCopyBuffer(cb, on_device_->handle(), host_->handle(), 1, &region);
      });
    };
    out.setup_s =
        device_setup_s_ + wall_seconds([&] {
          if (bytes > capacity_) {
            capacity_ = 0;
            host_.reset();
            on_device_.reset();
            on_device_.emplace(*device_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               "the link's device buffer");
            host_.emplace(*device_, bytes, 0, "the link's host buffer");
            if (!host_->mapped())
              throw std::runtime_error("no host-visible memory for the link's host buffer");
            capacity_ = bytes;
          }
          fill(bytes, 0);
          upload();
          read_back();
        });
    device_setup_s_ = 0;
    out.device = device_->record();
    out.method =
        "vkCmdCopyBuffer between a host-visible (host-cached where offered) buffer and a buffer "
        "allocated as strategy outputs are (device-local first), both kept for the run; wall clock "
        "around submission and fence wait";
    for (int k = 0; k < repetitions; ++k) {
      // A word no earlier pass wrote goes up; the host copy is then overwritten, so the word can
      // only come back by the read-back: a copy that did not happen fails instead of timing
      // nothing.
      const std::uint32_t word = ++word_;
      fill(bytes, word);
      out.upload_s.push_back(wall_seconds(upload));
      fill(bytes, ~word);
      out.read_back_s.push_back(wall_seconds(read_back));
      check(bytes, word);
    }
    return out;
  }

 private:
  std::uint32_t* host_words() { return static_cast<std::uint32_t*>(host_->mapped()); }
  void fill(std::size_t bytes, std::uint32_t word) { std::fill_n(host_words(), bytes / 4, word); }
  void check(std::size_t bytes, std::uint32_t word) {
    const std::uint32_t* words = host_words();
    const std::size_t n = bytes / 4;
    for (const std::size_t k : {std::size_t{0}, n / 2, n - 1})
      if (words[k] != word)
        throw std::runtime_error(fmt::format(
            "link copy: word {} of {} read back as {:#x}, {:#x} was sent", k, n, words[k], word));
  }

  double device_setup_s_ = 0;
  std::optional<Device> device_;
  std::optional<Buffer> on_device_, host_;
  std::size_t capacity_ = 0;
  std::uint32_t word_ = 0;
};

}  // namespace

std::unique_ptr<LinkCopy::Bench> make_link_bench(const StrategyOptions& options) {
  return std::make_unique<LinkBench>(device_option(options));
}

}  // namespace nurbs::vulkan
