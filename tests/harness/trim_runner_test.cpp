// Trimmed scenes through the runner, with the reference's exact classifier: the classify phase,
// the record's trimming, scoring over the inside, a strategy that trims without a mask, reversed
// faces. The scene is the trimmed plate of plates.h, whose classification is known by hand.
#include <gtest/gtest.h>

#include <functional>

#include "harness/runner.h"
#include "tests/harness/plates.h"

namespace nurbs {
namespace {

using test::hand_distance;
using test::hand_inside;
using test::trimmed_plate;

// 9x9: u, v = k/8; 40 samples inside the face (trim_metrics_test.cpp counts them).
constexpr std::size_t kInside = 40;

EvalRequest grid9(bool normals = false) {
  Sampling grid;
  grid.grid_u = grid.grid_v = 9;
  return EvalRequest{grid, Precision::f64, normals};
}

// cpu-coxdeboor with its classify() calls counted and its read-back altered by `alter`.
class HookedStrategy final : public Strategy {
 public:
  HookedStrategy(int& classified, std::function<void(EvalResult&)> alter)
      : inner_(find_strategy("cpu-coxdeboor")->create({})),
        classified_(classified),
        alter_(std::move(alter)) {}
  std::string_view name() const override { return "hooked"; }
  Capabilities capabilities() const override { return inner_->capabilities(); }
  DeviceInfo device() const override { return inner_->device(); }
  void prepare_checked(const Scene& s, const EvalRequest& r) override { inner_->prepare(s, r); }
  void evaluate() override { inner_->evaluate(); }
  bool classify() override {
    ++classified_;
    return inner_->classify();
  }
  EvalResult read_back() override {
    EvalResult result = inner_->read_back();
    alter_(result);
    return result;
  }

 private:
  std::unique_ptr<Strategy> inner_;
  int& classified_;
  std::function<void(EvalResult&)> alter_;
};

StrategyEntry hooked_entry(int& classified, std::function<void(EvalResult&)> alter) {
  StrategyEntry entry = *find_strategy("cpu-coxdeboor");
  entry.create = [&classified, alter](const StrategyOptions&) -> std::unique_ptr<Strategy> {
    return std::make_unique<HookedStrategy>(classified, alter);
  };
  return entry;
}

TEST(TrimReference, ClassifiesThePlateAsByHand) {
  // The premise of the runner tests below: the reference's classification and distances are the
  // closed forms (distances to 1% away from the boundary, as reference/trim_classify.h states).
  const Scene scene = trimmed_plate();
  ReferenceCache references;
  const ReferenceSurface& ref = references.get(scene, grid9())[0];
  const SurfaceSamples samples = sample_parameters(scene, grid9().sampling)[0];
  ASSERT_EQ(ref.inside.size(), 81u);
  for (std::size_t k = 0; k < 81; ++k) {
    const double u = samples.u_of(k), v = samples.v_of(k);
    EXPECT_EQ(ref.inside[k], hand_inside(u, v) ? 1 : 0) << u << "," << v;
    EXPECT_NEAR(ref.trim_distance[k], hand_distance(u, v), 0.01 * hand_distance(u, v));
  }
}

TEST(TrimRunner, TrimmingStrategyIsTimedAndScoredForClassification) {
  const Scene scene = trimmed_plate();
  ReferenceCache references;
  int classified = 0;
  const Record r =
      measure(hooked_entry(classified, [](EvalResult&) {}), {}, scene, grid9(), 3, references);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_EQ(r.trimming, "classified");
  EXPECT_EQ(classified, 1 + 3 + 3) << "warm-up, the evaluate repetitions, the end-to-end ones";
  ASSERT_EQ(r.extra_phases.count("classify"), 1u);
  EXPECT_GT(r.extra_phases.at("classify").min_s, 0.0);
  ASSERT_TRUE(r.accuracy && r.accuracy->trim);
  const TrimAccuracy& t = *r.accuracy->trim;
  EXPECT_EQ(t.inside, kInside);
  EXPECT_EQ(t.boundary, 0u);
  EXPECT_EQ(t.misclassified, 0u) << "the reference's classifier in double, far from the boundary";
  EXPECT_EQ(t.misclassified_rate, 0.0);
  EXPECT_LT(r.accuracy->max_ulp, 4.0);
}

TEST(TrimRunner, MisclassificationAndBandReachTheRecord) {
  const Scene scene = trimmed_plate();
  ReferenceCache references;
  int classified = 0;
  // The hole's centre (u = v = 0.5, index 4 * 9 + 4) called inside.
  const Record r =
      measure(hooked_entry(classified, [](EvalResult& e) { e.surfaces[0].inside.at(40) = 1; }), {},
              scene, grid9(), 1, references, 0.04);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  const TrimAccuracy& t = *r.accuracy->trim;
  EXPECT_EQ(t.band, 0.04);
  EXPECT_EQ(t.boundary, 12u) << "the samples 0.05 beside the hole, within 0.04 x sqrt(2)";
  EXPECT_EQ(t.misclassified, 1u);
  EXPECT_DOUBLE_EQ(*t.misclassified_rate, 1.0 / (81 - 12));
}

TEST(TrimRunner, TrimmingStrategyWithoutAMaskIsAFailedMeasurement) {
  const Scene scene = trimmed_plate();
  ReferenceCache references;
  int classified = 0;
  const Record r =
      measure(hooked_entry(classified, [](EvalResult& e) { e.surfaces[0].inside.clear(); }), {},
              scene, grid9(), 1, references);
  EXPECT_EQ(r.status, Status::failed);
  EXPECT_NE(r.reason.find("no inside mask for trimmed surface 'plate'"), std::string::npos)
      << r.reason;
  EXPECT_EQ(r.trimming, "classified");
}

TEST(TrimRunner, StrategyThatDoesNotTrimIsLabelledUntrimmedNotFailed) {
  const Scene scene = trimmed_plate();
  ReferenceCache references;
  const Record r = measure(*find_strategy("cpu-horner"), {}, scene, grid9(), 1, references);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_EQ(r.trimming, "untrimmed");
  EXPECT_EQ(r.extra_phases.count("classify"), 0u);
  ASSERT_TRUE(r.accuracy && r.accuracy->trim);
  EXPECT_EQ(r.accuracy->trim->inside, kInside);
  EXPECT_FALSE(r.accuracy->trim->misclassified);
}

TEST(TrimRunner, UntrimmedSceneHasNoClassifyPhase) {
  Scene scene = trimmed_plate();
  scene.surfaces[0].trim.reset();
  ReferenceCache references;
  int classified = 0;
  const Record r =
      measure(hooked_entry(classified, [](EvalResult&) {}), {}, scene, grid9(), 2, references);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_EQ(classified, 0);
  EXPECT_EQ(r.trimming, "");
  EXPECT_TRUE(r.extra_phases.empty());
  EXPECT_FALSE(r.accuracy->trim);
}

TEST(TrimRunner, DeformingFramesClassifyEveryFrame) {
  const Scene scene = trimmed_plate();
  int classified = 0;
  const Record r = measure_deforming(hooked_entry(classified, [](EvalResult&) {}), {}, scene,
                                     grid9(), 4, ReferencePrecision::long_double);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  EXPECT_EQ(classified, 1 + 4);
  ASSERT_EQ(r.extra_phases.count("classify"), 1u);
  EXPECT_EQ(r.accuracy->trim->inside, kInside);
  EXPECT_EQ(r.accuracy->trim->misclassified, 0u);
}

TEST(TrimRunner, ReversedFaceNormalsAreScoredAsTheFacesNormals) {
  Scene scene = trimmed_plate();
  scene.surfaces[0].reversed = true;
  ReferenceCache references;
  // cpu-coxdeboor computes S_u x S_v = +z on the plate; the face's normal is -z.
  const Record r = measure(*find_strategy("cpu-coxdeboor"), {}, scene, grid9(true), 1, references);
  ASSERT_EQ(r.status, Status::ok) << r.reason;
  ASSERT_TRUE(r.accuracy->max_normal_angle_deg);
  EXPECT_LT(*r.accuracy->max_normal_angle_deg, 1e-6);
}

}  // namespace
}  // namespace nurbs
