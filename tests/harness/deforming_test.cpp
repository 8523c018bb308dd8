// The deforming-surface benchmark: the wave is a pure function of (scene, frame) that moves only
// points; measure_deforming's accuracy is that of the deformed scene, so a strategy whose update
// did nothing is caught; a strategy without updates_control_points is prepared again, and the
// record says so.
#include "scenes/deforming.h"

#include <gtest/gtest.h>

#include <cmath>

#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs {
namespace {

TEST(DeformingScene, PureFunctionOfSceneAndFrameMovingOnlyPoints) {
  const Scene base = *make_builtin_scene("duck");
  const Scene a = deformed_scene(base, 7), b = deformed_scene(base, 7);
  Scene reused = deformed_scene(base, 3);
  deform_scene(base, 7, reused);  // into a scene holding another frame
  const double amplitude = base.bounding_box_diagonal() / 50;
  double largest_move = 0;
  for (std::size_t i = 0; i < base.surfaces.size(); ++i) {
    const Surface &s = base.surfaces[i], &d = a.surfaces[i];
    EXPECT_EQ(d.knots_u, s.knots_u);
    EXPECT_EQ(d.knots_v, s.knots_v);
    EXPECT_EQ(d.weights, s.weights);
    EXPECT_EQ(d.points, b.surfaces[i].points);
    EXPECT_EQ(d.points, reused.surfaces[i].points);
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      EXPECT_EQ(d.points[k][0], s.points[k][0]);
      EXPECT_EQ(d.points[k][1], s.points[k][1]);
      const double expected = amplitude * std::sin(2 * M_PI * (s.points[k][0] + s.points[k][1]) /
                                                       (base.bounding_box_diagonal() / 2) +
                                                   2 * M_PI * 7 / kDeformingFramesPerPeriod);
      EXPECT_NEAR(d.points[k][2] - s.points[k][2], expected, 1e-12 * amplitude);
      largest_move = std::max(largest_move, std::fabs(d.points[k][2] - s.points[k][2]));
    }
  }
  EXPECT_GT(largest_move, 0.5 * amplitude);
  // Another frame is another shape.
  EXPECT_NE(deformed_scene(base, 8).surfaces[0].points, a.surfaces[0].points);
}

// A trimmed, reversed face keeps its trim and orientation in every frame, also when deformed into
// a scene that held another (untrimmed) surface.
TEST(DeformingScene, KeepsTrimsAndOrientation) {
  Scene base = *make_builtin_scene("trimmed-plate");
  base.surfaces[0].reversed = true;
  Scene reused = *make_builtin_scene("trimmed-plate");
  reused.surfaces[0].trim.reset();
  deform_scene(base, 5, reused);
  for (const Scene& frame : {deformed_scene(base, 5), reused}) {
    ASSERT_TRUE(frame.surfaces[0].trim.has_value());
    EXPECT_EQ(frame.surfaces[0].trim->loops.size(), base.surfaces[0].trim->loops.size());
    EXPECT_EQ(frame.surfaces[0].trim->loops[1].curves[0].points,
              base.surfaces[0].trim->loops[1].curves[0].points);
    EXPECT_TRUE(frame.surfaces[0].reversed);
  }
}

// Wraps a real strategy; its update_control_points does nothing (the interface's default), and
// its capabilities claim `claims_updates`.
class StaleUpdate final : public Strategy {
 public:
  explicit StaleUpdate(std::unique_ptr<Strategy> inner) : inner_(std::move(inner)) {}
  std::string_view name() const override { return "stale"; }
  Capabilities capabilities() const override { return inner_->capabilities(); }
  DeviceInfo device() const override { return inner_->device(); }
  void prepare_checked(const Scene& s, const EvalRequest& r) override { inner_->prepare(s, r); }
  void evaluate() override { inner_->evaluate(); }
  EvalResult read_back() override { return inner_->read_back(); }

 private:
  std::unique_ptr<Strategy> inner_;
};

StrategyEntry stale_entry(bool claims_updates) {
  StrategyEntry e = *find_strategy("cpu-coxdeboor");
  e.name = "stale";
  e.capabilities = [claims_updates] {
    Capabilities c = find_strategy("cpu-coxdeboor")->capabilities();
    c.updates_control_points = claims_updates;
    return c;
  };
  e.create = [](const StrategyOptions& o) -> std::unique_ptr<Strategy> {
    return std::make_unique<StaleUpdate>(find_strategy("cpu-coxdeboor")->create(o));
  };
  return e;
}

EvalRequest request(Precision precision) {
  Sampling grid;
  grid.grid_u = 19;
  grid.grid_v = 17;
  return {grid, precision, false};
}

// cpu-bezier re-decomposes the moved net; cpu-horner keeps its basis tables (004) and swaps the
// net: both must land on the last frame's surface.
TEST(MeasureDeforming, CpuUpdatersMatchTheDeformedReference) {
  const Scene scene = *make_builtin_scene("patch144");
  for (const char* strategy : {"cpu-bezier", "cpu-horner"})
    for (Precision precision : {Precision::f32, Precision::f64}) {
      SCOPED_TRACE(strategy);
      const Record r = measure_deforming(*find_strategy(strategy), StrategyOptions{}, scene,
                                         request(precision), 4, ReferencePrecision::long_double);
      ASSERT_EQ(r.status, Status::ok) << r.reason;
      ASSERT_TRUE(r.accuracy.has_value());
      EXPECT_LE(r.accuracy->max_ulp, precision == Precision::f32 ? 32.0 : 1e-6);
      ASSERT_TRUE(r.extra_phases.count("frame"));
      EXPECT_TRUE(r.extra_phases.count("frame_update"));
      EXPECT_FALSE(r.extra_phases.count("frame_prepare"));
      EXPECT_EQ(r.figures.at("frames"), 4);
      EXPECT_EQ(r.repetitions, 4);
      EXPECT_GT(r.extra_phases.at("frame").median_s, 0);
    }
}

// The check that would fail if an update did nothing: a strategy that claims to update but keeps
// frame 0's points is measured against the last frame and misses it by the wave's motion.
TEST(MeasureDeforming, AnUpdateThatDoesNothingIsCaught) {
  const Scene scene = *make_builtin_scene("patch144");
  const Record r = measure_deforming(stale_entry(true), StrategyOptions{}, scene,
                                     request(Precision::f64), 5, ReferencePrecision::long_double);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_GT(r.accuracy->max_abs, 0.1 * scene.bounding_box_diagonal() / 50);
  EXPECT_GT(r.accuracy->max_ulp, 1000);
}

// Without updates_control_points the harness prepares again inside the frame, and says so.
TEST(MeasureDeforming, StrategiesWithoutUpdatesArePreparedAgain) {
  const Scene scene = *make_builtin_scene("patch144");
  const Record r = measure_deforming(stale_entry(false), StrategyOptions{}, scene,
                                     request(Precision::f64), 3, ReferencePrecision::long_double);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_LE(r.accuracy->max_ulp, 1e-6);
  EXPECT_TRUE(r.extra_phases.count("frame_prepare"));
  EXPECT_FALSE(r.extra_phases.count("frame_update"));
}

TEST(MeasureDeforming, RefusedAndUnavailableAreResults) {
  const Scene scene = *make_builtin_scene("patch144");
  StrategyEntry e = *find_strategy("cpu-tensor");
  EvalRequest explicit_request = request(Precision::f32);
  explicit_request.sampling.mode = SamplingMode::explicit_list;
  explicit_request.sampling.explicit_uv = {{{0.5, 0.5}}};
  const Record refused = measure_deforming(e, StrategyOptions{}, scene, explicit_request, 2,
                                           ReferencePrecision::long_double);
  EXPECT_EQ(refused.status, Status::refused);
  e.probe = [] { return Availability{false, "not here"}; };
  const Record unavailable = measure_deforming(e, StrategyOptions{}, scene, request(Precision::f32),
                                               2, ReferencePrecision::long_double);
  EXPECT_EQ(unavailable.status, Status::unavailable);
  EXPECT_EQ(unavailable.reason, "not here");
}

}  // namespace
}  // namespace nurbs
