#include "strategies/device_copy.h"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

#if NURBSBENCH_DEVICE_COPY_VULKAN
#include "strategies/device_wait.h"
#include "strategies/vulkan/vk_copy_bandwidth.h"
#include "strategies/vulkan/vk_device.h"
#endif

namespace nurbs {

#if NURBSBENCH_DEVICE_COPY_VULKAN
struct DeviceCopy::Bench {
  explicit Bench(const StrategyOptions& options) : copies(vulkan::device_option(options)) {}
  vulkan::CopyBench copies;
};
#else
struct DeviceCopy::Bench {};
#endif

DeviceCopy::DeviceCopy(StrategyOptions options) : options_(std::move(options)) {}

DeviceCopy::~DeviceCopy() = default;

const Availability& DeviceCopy::availability() {
  if (!availability_) {
#if NURBSBENCH_DEVICE_COPY_VULKAN
    // A --device out of range is the copy's error, as it is a strategy's.
    availability_ = vulkan::probe(vulkan::Requirements{});
#else
    availability_ = Availability{false, "not built with Vulkan"};
#endif
  }
  return *availability_;
}

DeviceCopyTiming DeviceCopy::time(std::size_t bytes, int repetitions) {
#if NURBSBENCH_DEVICE_COPY_VULKAN
  try {
    if (!bench_) bench_ = std::make_unique<Bench>(options_);
    return bench_->copies.time(bytes, repetitions);
  } catch (const DeviceTimeout& e) {
    // A device that stopped answering cannot be torn down without an unbounded wait (Device's
    // destructor idles it): it is left as it is, and the run's later copies are unavailable
    // instead of each waiting out the limit again.
    static_cast<void>(bench_.release());
    availability_ = Availability{false, fmt::format("the device did not answer an earlier copy "
                                                    "of this run: {}",
                                                    e.what())};
    throw;
  } catch (...) {
    // After a failed call the device's state is unknown: the next copy opens it again.
    bench_.reset();
    throw;
  }
#else
  (void)bytes, (void)repetitions;
  throw std::runtime_error("not built with Vulkan");
#endif
}

}  // namespace nurbs
