// The limit-link-opencl row's copies (strategies/opencl/cl_link_bandwidth.cpp) through LinkCopy,
// as the harness drives them: one timing per repetition in each direction, each positive, the
// device's record and the method in words; the device and the buffers are kept between calls
// (a later, smaller request pays no device or buffer setup) and grown for a larger one, whose
// content check must pass too.
#include <gtest/gtest.h>

#include <string>

#include "strategies/link_copy.h"

namespace nurbs {
namespace {

void expect_timings(const LinkTiming& t, int repetitions) {
  ASSERT_EQ(t.upload_s.size(), static_cast<std::size_t>(repetitions));
  ASSERT_EQ(t.read_back_s.size(), static_cast<std::size_t>(repetitions));
  for (double s : t.upload_s) EXPECT_GT(s, 0);
  for (double s : t.read_back_s) EXPECT_GT(s, 0);
  EXPECT_GE(t.setup_s, 0);
}

TEST(OpenClLink, TimesEachRepetitionAndKeepsTheDevice) {
  LinkCopy link(LinkApi::opencl, StrategyOptions{});
  const Availability& available = link.availability();
  if (!available.available) GTEST_SKIP() << "unavailable: " << available.reason;

  constexpr std::size_t kLarge = 16u << 20, kSmall = 4096;
  const LinkTiming first = link.time(kLarge, 3);
  expect_timings(first, 3);
  EXPECT_FALSE(first.device.name.empty());
  EXPECT_TRUE(first.device.details.count("platform"));
  EXPECT_NE(first.method.find("CL_MEM_ALLOC_HOST_PTR"), std::string::npos) << first.method;

  // Kept: no device to open, no buffer to allocate, two untimed copies of 4 KiB -- against the
  // first call's device, 2 x 16 MiB of fresh buffers and their first touches.
  const LinkTiming second = link.time(kSmall, 2);
  expect_timings(second, 2);
  EXPECT_EQ(second.device.name, first.device.name);
  EXPECT_LT(second.setup_s, first.setup_s);

  // Grown: the copies of the larger request reach its last word (the content check throws if not).
  const LinkTiming third = link.time(2 * kLarge, 1);
  expect_timings(third, 1);
}

}  // namespace
}  // namespace nurbs
