// The limit-device-copy row (harness/copy_limit.h): what it measures where there is a Vulkan
// device (lavapipe in CI), what it says where there is none, and which strategies it is a
// ceiling for.
#include "harness/copy_limit.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

#include "harness/store_limit.h"
#include "scenes/builtin_scenes.h"
#include "strategies/device_copy.h"

namespace nurbs {
namespace {

TEST(DeviceCopyLimit, RowTimesACopyOfTheRequestsOutputOrSaysWhyNot) {
  const Scene scene = *make_builtin_scene("many-4");
  Sampling grid;
  grid.grid_u = 32;
  grid.grid_v = 16;
  const EvalRequest request{grid, Precision::f32, true};  // 24 bytes a point
  DeviceCopy device_copy(StrategyOptions{});
  const Record r = measure_device_copy_limit(scene, request, 2, device_copy);
  EXPECT_EQ(r.strategy, "limit-device-copy");
  EXPECT_EQ(r.role, "limit");
  EXPECT_EQ(r.points, 4u * 32 * 16);
  EXPECT_EQ(r.samples, "32x16");
  EXPECT_FALSE(r.accuracy);
  const Availability availability = device_copy.availability();
  if (!availability.available) {
    EXPECT_EQ(r.status, Status::unavailable);
    EXPECT_EQ(r.reason, availability.reason);
    // The release build with every backend (scripts/test.sh) has lavapipe: no excuse there.
    if (std::getenv("NURBSBENCH_REQUIRE_ALL_STRATEGIES")) {
      EXPECT_EQ(availability.reason, "not built with Vulkan");
    }
    return;
  }
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_FALSE(r.device.name.empty());
  EXPECT_EQ(r.device.details.at("clock"), "device timestamps");
  // lavapipe's copy is the host's memcpy: a CPU figure.
  if (r.device.name.find("llvmpipe") != std::string::npos) {
    EXPECT_EQ(r.device.kind, "cpu");
  }
  EXPECT_GT(r.evaluate.min_s, 0.0);
  EXPECT_LE(r.evaluate.min_s, r.evaluate.median_s);
  EXPECT_DOUBLE_EQ(r.throughput_pts_per_s, r.points / r.evaluate.median_s);
  EXPECT_DOUBLE_EQ(r.figures.at("copy_bytes_per_s"), 24 * r.throughput_pts_per_s);
  EXPECT_EQ(r.figures.at("bytes_per_point"), 24.0);
  // A few KiB of output; the copy still goes through memory, as the store pass does.
  EXPECT_EQ(r.figures.at("pass_bytes"), static_cast<double>(store_pass_bytes(r.points * 24)));
  EXPECT_GT(r.setup_s, 0.0);
  // The session's next row copies on the same device and buffers, and copies again: the new
  // words arrive (the row would be failed otherwise).
  const Record again = measure_device_copy_limit(scene, request, 3, device_copy);
  ASSERT_EQ(again.status, Status::ok) << again.reason;
  EXPECT_EQ(again.device.name, r.device.name);
  EXPECT_EQ(again.repetitions, 3);
  EXPECT_GT(again.evaluate.min_s, 0.0);
  // A larger request grows the buffers.
  grid.grid_u = 1536;
  grid.grid_v = 1024;
  const Record larger =
      measure_device_copy_limit(scene, EvalRequest{grid, Precision::f32, true}, 1, device_copy);
  ASSERT_EQ(larger.status, Status::ok) << larger.reason;
  EXPECT_EQ(larger.figures.at("pass_bytes"),
            static_cast<double>(store_pass_bytes(larger.points * 24)));
  EXPECT_GT(larger.figures.at("pass_bytes"), r.figures.at("pass_bytes"));
}

TEST(DeviceCopyLimit, CopyOfAByteCountNotAWholeWordIsRefusedByTheCaller) {
  DeviceCopy device_copy(StrategyOptions{});
  if (!device_copy.availability().available) GTEST_SKIP() << "no Vulkan device";
  EXPECT_THROW(device_copy.time(6, 1), std::invalid_argument);
  // The refusal is the caller's mistake, not the device's: the next copy still runs.
  EXPECT_EQ(device_copy.time(1 << 20, 1).seconds.size(), 1u);
}

Record row(std::string strategy, std::string role, std::string device, double points_per_s) {
  Record r;
  r.scene = "patch144";
  r.strategy = std::move(strategy);
  r.role = std::move(role);
  const std::string kind = device == "host CPU" ? "cpu" : "gpu";
  r.device = {std::move(device), kind, {}};
  r.precision = "f32";
  r.samples = "4096x4096";
  r.points = 4096u * 4096;
  r.throughput_pts_per_s = points_per_s;
  r.figures["bytes_per_point"] = 12;
  return r;
}

// Each fraction takes its own limit row, whichever comes last, and the copy is a ceiling only for
// strategies on the device that copied.
TEST(DeviceCopyLimit, FractionIsOfTheCopyOnTheSameDeviceOnly) {
  const Record store = row(std::string(kStoreLimitName), "limit", "host CPU", 2e9);
  const Record copy = row(std::string(kDeviceCopyLimitName), "limit", "NVIDIA H100", 1e11);
  const Record on_gpu = row("vk-compute", "strategy", "NVIDIA H100", 5e10);
  const Record on_host = row("cpu-tensor", "strategy", "host CPU", 1e9);
  const std::vector<Record> records = {store, copy, on_gpu, on_host};
  ASSERT_TRUE(fraction_of_device_copy_limit(on_gpu, records));
  EXPECT_DOUBLE_EQ(*fraction_of_device_copy_limit(on_gpu, records), 0.5);
  EXPECT_FALSE(fraction_of_device_copy_limit(on_host, records));
  EXPECT_FALSE(fraction_of_device_copy_limit(copy, records));
  ASSERT_TRUE(fraction_of_store_limit(on_host, records));
  EXPECT_DOUBLE_EQ(*fraction_of_store_limit(on_host, records), 0.5);
  // A GPU does not write through the host's stores: no store fraction for it.
  EXPECT_FALSE(fraction_of_store_limit(on_gpu, records));
  // Under the stated size the copy times the submission, not the memory.
  Record small = copy;
  small.points = 64 * 64;
  EXPECT_FALSE(fraction_of_device_copy_limit(on_gpu, {store, small, on_gpu}));
  // A failed copy is no ceiling.
  Record failed = copy;
  failed.status = Status::failed;
  EXPECT_FALSE(fraction_of_device_copy_limit(on_gpu, {failed, on_gpu}));
}

}  // namespace
}  // namespace nurbs
