// The GL row of the host<->device link (strategies/gl_context/gl_link_bandwidth.cpp) through its
// front (strategies/link_copy.h): one timing per repetition each way, all positive, the device the
// GL strategies record, a second call on the context and buffers of the first, a request beyond
// the driver's texture limits refused before anything is allocated.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "strategies/gl_context/gl_context.h"
#include "strategies/link_copy.h"

namespace nurbs {
namespace {

class GlLinkBandwidth : public ::testing::TestWithParam<std::string> {
 protected:
  StrategyOptions options() const {
    StrategyOptions o;
    o.extra["gl"] = GetParam();
    return o;
  }
  bool available() const { return gl::Context::probe(*gl::parse_platform(GetParam())).available; }
};

TEST_P(GlLinkBandwidth, TimesEveryRepetitionEachWay) {
  if (!available()) GTEST_SKIP() << GetParam() << " unavailable";
  LinkCopy link(LinkApi::gl, options());
  ASSERT_TRUE(link.availability().available) << link.availability().reason;
  // Not a multiple of a texture row: the last row is a part one.
  const std::size_t bytes = (std::size_t{1} << 20) + 64;
  const LinkTiming first = link.time(bytes, 3);
  ASSERT_EQ(first.upload_s.size(), 3u);
  ASSERT_EQ(first.read_back_s.size(), 3u);
  for (double s : first.upload_s) EXPECT_GT(s, 0.0);
  for (double s : first.read_back_s) EXPECT_GT(s, 0.0);
  EXPECT_GT(first.setup_s, 0.0);
  EXPECT_FALSE(first.method.empty());
  EXPECT_EQ(first.device.details.count("gl_renderer"), 1u);
  EXPECT_FALSE(first.device.name.empty());

  // The context and buffers stay: the second call's setup is its untimed copies only, not a
  // context's creation; a smaller request keeps the buffers, a larger one grows them.
  const LinkTiming second = link.time(bytes / 2, 2);
  EXPECT_EQ(second.upload_s.size(), 2u);
  EXPECT_EQ(second.read_back_s.size(), 2u);
  EXPECT_LT(second.setup_s, first.setup_s);
  EXPECT_EQ(second.device.name, first.device.name);
  const LinkTiming third = link.time(2 * bytes, 1);
  EXPECT_EQ(third.upload_s.size(), 1u);
  EXPECT_GT(third.read_back_s.front(), 0.0);
}

TEST_P(GlLinkBandwidth, RefusesWhatNoTextureHolds) {
  if (!available()) GTEST_SKIP() << GetParam() << " unavailable";
  const auto context = gl::Context::create(*gl::parse_platform(GetParam()));
  const std::size_t side = static_cast<std::size_t>(context->max_texture_size());
  LinkCopy link(LinkApi::gl, options());
  EXPECT_THROW(link.time(side * side * 16 + 16, 1), RefusedError);
}

INSTANTIATE_TEST_SUITE_P(Platforms, GlLinkBandwidth, ::testing::Values("osmesa", "egl"),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace nurbs
