// The limit-link-<api> rows (harness/link_limit.h): what they measure on each API's device
// (lavapipe, PoCL and llvmpipe in CI), what they say where there is none, and which strategies'
// transfer phases they are a ceiling for.
#include "harness/link_limit.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "harness/store_limit.h"
#include "scenes/builtin_scenes.h"
#include "strategies/link_copy.h"

namespace nurbs {
namespace {

class LinkLimitRow : public ::testing::TestWithParam<LinkApi> {};

TEST_P(LinkLimitRow, CopiesTheResultsBytesBothWaysOrSaysWhyNot) {
  const Scene scene = *make_builtin_scene("many-4");
  Sampling grid;
  grid.grid_u = 32;
  grid.grid_v = 16;
  const EvalRequest request{grid, Precision::f64, false};  // 24 bytes a point
  LinkCopy link(GetParam(), StrategyOptions{});
  const Record r = measure_link_limit(scene, request, 3, link);
  EXPECT_EQ(r.strategy, link_limit_name(GetParam()));
  EXPECT_EQ(link_limit_api(r.strategy), GetParam());
  EXPECT_EQ(r.role, "limit");
  EXPECT_EQ(r.points, 4u * 32 * 16);
  EXPECT_FALSE(r.accuracy);
  const Availability availability = link.availability();
  if (!availability.available) {
    EXPECT_EQ(r.status, Status::unavailable);
    EXPECT_EQ(r.reason, availability.reason);
    // The release build with every backend (scripts/test.sh) has all three software drivers.
    if (std::getenv("NURBSBENCH_REQUIRE_ALL_STRATEGIES")) {
      ADD_FAILURE() << "no " << link_api_name(GetParam()) << " device: " << availability.reason;
    }
    return;
  }
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_FALSE(r.device.name.empty());
  // The row is recognised as its API's by the same rule that finds a strategy's API.
  EXPECT_EQ(link_api_of(r.device), GetParam());
  EXPECT_FALSE(r.device.details.at("kernel").empty());
  EXPECT_EQ(r.repetitions, 3);
  EXPECT_LE(r.read_back.min_s, r.read_back.median_s);
  EXPECT_GT(r.read_back.min_s, 0.0);
  EXPECT_GT(r.upload.min_s, 0.0);
  EXPECT_DOUBLE_EQ(r.figures.at("bytes"), 4.0 * 32 * 16 * 24);
  EXPECT_DOUBLE_EQ(r.figures.at("read_back_bytes_per_s"),
                   r.figures.at("bytes") / r.read_back.median_s);
  EXPECT_DOUBLE_EQ(r.throughput_pts_per_s, r.points / r.read_back.median_s);
  // The session's next row reuses the device and copies again (new words must arrive, or the
  // row fails); a larger request grows the buffers.
  const Record again = measure_link_limit(scene, request, 1, link);
  ASSERT_EQ(again.status, Status::ok) << again.reason;
  EXPECT_EQ(again.device.name, r.device.name);
  grid.grid_u = 512;
  grid.grid_v = 512;
  const Record larger = measure_link_limit(scene, EvalRequest{grid, Precision::f32, true}, 1, link);
  ASSERT_EQ(larger.status, Status::ok) << larger.reason;
  EXPECT_DOUBLE_EQ(larger.figures.at("bytes"), 4.0 * 512 * 512 * 24);
}

INSTANTIATE_TEST_SUITE_P(EveryApi, LinkLimitRow, ::testing::ValuesIn(kLinkApis),
                         [](const ::testing::TestParamInfo<LinkApi>& info) {
                           return std::string(link_api_name(info.param));
                         });

Record record(std::string strategy, std::string role, DeviceInfo device) {
  Record r;
  r.scene = "patch144";
  r.strategy = std::move(strategy);
  r.role = std::move(role);
  r.device = std::move(device);
  r.precision = "f32";
  r.samples = "4096x4096";
  r.points = 4096u * 4096;
  r.throughput_pts_per_s = 1e9;
  return r;
}

// The GL paths' ceiling: a trivial fragment pass over one pixel per point, on the GL link's
// context, its output checked (a pass that did not draw fails the row).
TEST(FragmentPassLimit, PassesOverOnePixelPerPointOrSaysWhyNot) {
  const Scene scene = *make_builtin_scene("many-4");
  Sampling grid;
  grid.grid_u = 300;  // 4 x 300 x 200 = 240,000 pixels: several rows of the widest target
  grid.grid_v = 200;
  LinkCopy gl(LinkApi::gl, StrategyOptions{});
  const Record r =
      measure_fragment_pass_limit(scene, EvalRequest{grid, Precision::f32, false}, 3, gl);
  EXPECT_EQ(r.strategy, "limit-gl-fragment-pass");
  EXPECT_EQ(r.role, "limit");
  if (!gl.availability().available) {
    EXPECT_EQ(r.status, Status::unavailable);
    if (std::getenv("NURBSBENCH_REQUIRE_ALL_STRATEGIES")) {
      ADD_FAILURE() << "no GL device: " << gl.availability().reason;
    }
    return;
  }
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_EQ(link_api_of(r.device), LinkApi::gl);
  EXPECT_GT(r.evaluate.min_s, 0.0);
  EXPECT_DOUBLE_EQ(r.throughput_pts_per_s, r.points / r.evaluate.median_s);
  ASSERT_TRUE(r.device_evaluate_median_s);
  EXPECT_GT(*r.device_evaluate_median_s, 0.0);
  // Another API has no such ceiling: the row says so instead of timing nothing.
  LinkCopy vulkan(LinkApi::vulkan, StrategyOptions{});
  if (vulkan.availability().available) {
    const Record none =
        measure_fragment_pass_limit(scene, EvalRequest{grid, Precision::f32, false}, 1, vulkan);
    EXPECT_EQ(none.status, Status::failed);
  }
}

TEST(LinkLimit, ApiOfADeviceIsReadFromWhatEachApiRecords) {
  EXPECT_EQ(link_api_of({"NVIDIA H100", "gpu", {{"api", "Vulkan 1.3.277"}}}), LinkApi::vulkan);
  EXPECT_EQ(link_api_of({"NVIDIA H100",
                         "gpu",
                         {{"platform", "NVIDIA CUDA"}, {"device_version", "OpenCL 3.0 CUDA"}}}),
            LinkApi::opencl);
  EXPECT_EQ(link_api_of({"NVIDIA H100", "gpu", {{"gl_version", "4.6.0 NVIDIA"}}}), LinkApi::gl);
  EXPECT_FALSE(link_api_of({"host CPU", "cpu", {{"threads", "2"}}}));
}

// read_back: the row's time for the same bytes over the strategy's; upload: bandwidths, from the
// bytes the strategy says it sent. Only against the row of its own API and device.
TEST(LinkLimit, FractionsAreOfTheRowOfTheStrategysApiAndDevice) {
  const DeviceInfo gl{"NVIDIA H100", "gpu", {{"gl_version", "4.6.0 NVIDIA"}}};
  const DeviceInfo vk{"NVIDIA H100", "gpu", {{"api", "Vulkan 1.3"}}};
  Record link = record(link_limit_name(LinkApi::gl), "limit", gl);
  link.read_back = PhaseStats::of({0.004});
  link.upload = PhaseStats::of({0.002});
  link.figures["upload_bytes_per_s"] = 1e10;
  Record vk_link = record(link_limit_name(LinkApi::vulkan), "limit", vk);
  vk_link.read_back = PhaseStats::of({0.001});
  vk_link.figures["upload_bytes_per_s"] = 4e10;
  Record glsl = record("glsl-deboor", "strategy", gl);
  glsl.read_back = PhaseStats::of({0.016, 0.016, 0.020});
  glsl.upload = PhaseStats::of({0.001});
  glsl.device.details["bytes_uploaded"] = "5000000";  // 5e9 B/s: half the link's
  const std::vector<Record> records = {link, vk_link, glsl};
  ASSERT_TRUE(fraction_of_link(glsl, records, LinkPhase::read_back));
  EXPECT_DOUBLE_EQ(*fraction_of_link(glsl, records, LinkPhase::read_back), 0.25);
  ASSERT_TRUE(fraction_of_link(glsl, records, LinkPhase::upload));
  EXPECT_DOUBLE_EQ(*fraction_of_link(glsl, records, LinkPhase::upload), 0.5);
  // Without the bytes it sent, no upload fraction; on another device, none at all.
  Record silent = glsl;
  silent.device.details.erase("bytes_uploaded");
  EXPECT_FALSE(fraction_of_link(silent, records, LinkPhase::upload));
  Record elsewhere = glsl;
  elsewhere.device.name = "llvmpipe (LLVM 15.0.6, 256 bits)";
  EXPECT_FALSE(fraction_of_link(elsewhere, records, LinkPhase::read_back));
  // A host strategy has no link; nor has a limit row or a failed record.
  EXPECT_FALSE(fraction_of_link(record("cpu-tensor", "baseline", {"host CPU", "cpu", {}}), records,
                                LinkPhase::read_back));
  EXPECT_FALSE(fraction_of_link(link, records, LinkPhase::read_back));
  Record failed = glsl;
  failed.status = Status::failed;
  EXPECT_FALSE(fraction_of_link(failed, records, LinkPhase::read_back));
  // Without a row of its API (only Vulkan's here), none.
  EXPECT_FALSE(fraction_of_link(glsl, {vk_link, glsl}, LinkPhase::read_back));
}

}  // namespace
}  // namespace nurbs
