// cl-stair's read-back into the harness's reused result (read_back_into) by both paths of
// strategies/opencl/cl_read_back.h -- straight into the result's storage, and through pinned
// staging -- on several ducks, every third trimmed: both paths give read_back()'s points and masks
// bit for bit, a second read-back keeps the result's storage, and the phases' device times and
// upload counts are recorded.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "reference/nurbs_math.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs {
namespace {

StrategyOptions read_back_option(const std::string& path) {
  StrategyOptions options;
  options.extra["read-back"] = path;
  return options;
}

bool same_bits(const PointArray& a, const PointArray& b) {
  return a.size() == b.size() && a.precision() == b.precision() &&
         (a.size() == 0 ||
          std::memcmp(a.data<float>(), b.data<float>(), a.size() * 3 * sizeof(float)) == 0);
}

TEST(cl_stair_read_back, BothPathsMatchAndReuseTheResult) {
  const StrategyEntry& entry = *find_strategy("cl-stair");
  const Availability a = entry.probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  const Scene scene = *make_builtin_scene("many-ducks-6");
  Sampling sampling;
  sampling.grid_u = 37;
  sampling.grid_v = 29;
  const EvalRequest request{sampling, Precision::f32, false};

  EvalResult expected;
  for (const std::string path : {"mapped", "staged"}) {
    SCOPED_TRACE(path);
    const auto strategy = entry.create(read_back_option(path));
    strategy->prepare(scene, request);
    strategy->evaluate();
    ASSERT_TRUE(strategy->classify());
    const EvalResult fresh = strategy->read_back();
    EvalResult reused;
    strategy->read_back_into(reused);
    const float* storage = reused.surfaces.front().positions.data<float>();
    strategy->read_back_into(reused);
    EXPECT_EQ(reused.surfaces.front().positions.data<float>(), storage);

    ASSERT_EQ(fresh.surfaces.size(), scene.surfaces.size());
    ASSERT_EQ(reused.surfaces.size(), scene.surfaces.size());
    if (expected.surfaces.empty()) expected = fresh;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      SCOPED_TRACE("surface " + std::to_string(i));
      EXPECT_TRUE(same_bits(fresh.surfaces[i].positions, reused.surfaces[i].positions));
      EXPECT_TRUE(same_bits(fresh.surfaces[i].positions, expected.surfaces[i].positions));
      EXPECT_EQ(fresh.surfaces[i].inside, reused.surfaces[i].inside);
      EXPECT_EQ(fresh.surfaces[i].inside, expected.surfaces[i].inside);
      EXPECT_EQ(fresh.surfaces[i].inside.size(),
                scene.surfaces[i].trim ? fresh.surfaces[i].samples.count() : 0u);
    }

    const DeviceTimes t = strategy->device_times();
    for (const auto& phase : {t.evaluate_s, t.upload_s, t.classify_s, t.read_back_s}) {
      ASSERT_TRUE(phase.has_value());
      EXPECT_GE(*phase, 0);
    }
    const auto details = strategy->device().details;
    EXPECT_EQ(details.at("read_back").rfind(path, 0), 0u) << details.at("read_back");
    EXPECT_GT(std::stoull(details.at("bytes_uploaded")), 0u);
    EXPECT_GE(std::stoull(details.at("work_groups")), std::stoull(details.at("ksquads")));

    // An update sends the control points only: 4 floats per point of every net.
    std::size_t reals = 0;
    for (const Surface& s : scene.surfaces) reals += 4 * s.count_u * s.count_v;
    strategy->update_control_points(scene);
    EXPECT_EQ(strategy->device().details.at("bytes_updated"), std::to_string(reals * 4));
  }
}

}  // namespace
}  // namespace nurbs
