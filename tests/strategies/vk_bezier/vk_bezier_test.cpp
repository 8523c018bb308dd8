// vk-bezier on the Vulkan device (lavapipe here: CPU figures): accuracy against the reference
// within a bound derived from its float arithmetic, the same tessellator lattice as vk-ksquad,
// control-point updates equal to a fresh prepare, degrees up to 15, and its refusals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cstring>
#include <iostream>

#include "harness/metrics.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "tests/reference/test_support.h"
#include "tests/strategies/domain_ends.h"

namespace nurbs {
namespace {

using test::grid;
using test::span_grid;

std::unique_ptr<Strategy> make(const char* name) {
  return find_strategy(name)->create(StrategyOptions{});
}

EvalResult run(Strategy& strategy, const Scene& scene, const Sampling& sampling,
               bool normals = false) {
  strategy.prepare(scene, EvalRequest{sampling, Precision::f32, normals});
  strategy.evaluate();
  return strategy.read_back();
}

// The bound, in measure_accuracy's ulps (FLT_EPSILON = 2u times the scene's largest coordinate),
// from the float arithmetic of bezier.tese at degrees (p, q), to first order in u = 2^-24:
//  * the homogeneous Bézier points rounded to float once (u each), the A1.3 triangles (p and q
//    levels of a*(1-t) + b*t: 2u per level on non-negative terms) and the (p+1)(q+1)-term sum
//    (p + q + 2 additions), all relative to sum |B w P|: (3 (p + q) + 4) u;
//  * the local parameter t = (u - x0) / (x1 - x0): 3u of t, through |dS/dt| <= 2 p max |P| (the
//    hodograph's points are p (P_k+1 - P_k)), and the same in v: 6 (p + q) u max |P|;
//  * both magnified by the weight ratio w_max / w_min (the divide by sum B w; the hodograph of a
//    rational patch), the NURBS net's ratio bounding the Bézier points' (their weights are convex
//    combinations of it);
//  * the divide and the patch origin's addition (its points are relative to it): 2u.
// A worst-case bound: measured on lavapipe far below it (<= 7.6 ulps, clustered span grids, where
// short spans amplify the local parameter's rounding; ~1 elsewhere; printed).
double derived_bound_ulps(const Scene& scene) {
  double worst = 0;
  for (const Surface& s : scene.surfaces) {
    const auto [lo, hi] = std::minmax_element(s.weights.begin(), s.weights.end());
    const double ratio = *hi / *lo;
    const int p = s.degree_u, q = s.degree_v;
    worst = std::max(worst, ((9.0 * (p + q) + 4) * ratio + 2) / 2);
  }
  return worst;
}

class VkBezierTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const Availability a = find_strategy("vk-bezier")->probe();
    if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
    strategy_ = make("vk-bezier");
  }
  std::unique_ptr<Strategy> strategy_;
};

// Grid (the requested samples, 33 x 29 so samples fall inside spans, not only on knots), span
// grid T = 16 and T = 100 (past the tessellator's cap of 64: runs cut into pieces of one Bézier
// patch). Normals within 0.1 degree (the shared suite allows 1; measured worst 0.0085, clustered
// span100; teapot, with collapsed edges, 1.7e-4): the Bernstein derivatives at a span's end knot
// are the next patch's, as the reference's on a crease.
TEST_F(VkBezierTest, WithinTheDerivedBoundOnBuiltinScenes) {
  for (const char* name : {"patch144", "teapot", "degree-5", "clustered", "degree-9", "creases"}) {
    const Scene scene = *make_builtin_scene(name);
    const double bound = derived_bound_ulps(scene);
    for (const Sampling& sampling : {grid(33, 29), span_grid(16), span_grid(100)}) {
      SCOPED_TRACE(std::string(name) + " " + sampling.label());
      const EvalResult result = run(*strategy_, scene, sampling, true);
      const auto produced = result_samples(result);
      if (sampling.mode == SamplingMode::grid) {
        EXPECT_TRUE(same_samples(produced, sample_parameters(scene, sampling)));
      }
      const Accuracy acc =
          measure_accuracy(scene, result, evaluate_reference(scene, produced, true));
      EXPECT_EQ(acc.non_finite, 0u);
      EXPECT_LE(acc.max_ulp, bound);
      ASSERT_TRUE(acc.max_normal_angle_deg.has_value());
      EXPECT_LE(*acc.max_normal_angle_deg, 0.1);
      std::cout << "vk-bezier " << name << " " << sampling.label() << ": max_ulp " << acc.max_ulp
                << " (bound " << bound << "), normals " << *acc.max_normal_angle_deg << " deg\n";
    }
  }
}

// The like-for-like claim of `run --deforming`: vk-bezier tessellates exactly vk-ksquad's lattice
// (the same control stage, levels and span parameters on the same float knots), so on a span
// grid both return the same samples, bit for bit; a grid's are the requested ones in both.
TEST_F(VkBezierTest, SpanGridSamplesAreVkKsquads) {
  if (!find_strategy("vk-ksquad")->probe().available) GTEST_SKIP() << "no vk-ksquad";
  const auto ksquad = make("vk-ksquad");
  for (const char* name : {"patch144", "teapot", "clustered"}) {
    const Scene scene = *make_builtin_scene(name);
    for (int steps : {5, 100}) {
      const auto mine = result_samples(run(*strategy_, scene, span_grid(steps)));
      const auto theirs = result_samples(run(*ksquad, scene, span_grid(steps)));
      ASSERT_EQ(mine.size(), theirs.size());
      for (std::size_t i = 0; i < mine.size(); ++i) {
        EXPECT_EQ(mine[i].tensor, theirs[i].tensor) << name;
        EXPECT_EQ(mine[i].u, theirs[i].u) << name << " surface " << i << " T=" << steps;
        EXPECT_EQ(mine[i].v, theirs[i].v) << name << " surface " << i << " T=" << steps;
      }
    }
  }
}

std::vector<float> positions_of(const EvalResult& r) {
  std::vector<float> out;
  for (const SurfaceResult& s : r.surfaces)
    out.insert(out.end(), s.positions.f32(), s.positions.f32() + 3 * s.positions.size());
  return out;
}

// update_control_points decomposes the moved nets and uploads the new Bézier points: the result
// is bit for bit a fresh prepare's of the moved scene, and not the unmoved one's.
TEST_F(VkBezierTest, UpdateControlPointsEqualsAFreshPrepare) {
  for (const char* name : {"teapot", "degree-5"}) {
    const Scene scene = *make_builtin_scene(name);
    Scene moved = scene;
    for (Surface& s : moved.surfaces)
      for (std::size_t k = 0; k < s.points.size(); ++k) {
        s.points[k][2] += 0.25 * s.points[k][0];
        s.weights[k] *= 1.0 + 0.125 * static_cast<double>(k % 3);  // weights move too
      }
    for (const Sampling& sampling : {grid(17, 13), span_grid(4)}) {
      SCOPED_TRACE(std::string(name) + " " + sampling.label());
      const std::vector<float> before = positions_of(run(*strategy_, scene, sampling));
      strategy_->update_control_points(moved);
      strategy_->evaluate();
      const EvalResult updated = strategy_->read_back();
      const auto fresh = make("vk-bezier");
      const EvalResult prepared = run(*fresh, moved, sampling);
      const std::vector<float> a = positions_of(updated), b = positions_of(prepared);
      ASSERT_EQ(a.size(), b.size());
      EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
      EXPECT_NE(a, before);
      const Accuracy acc = measure_accuracy(
          moved, updated, evaluate_reference(moved, result_samples(updated), false));
      EXPECT_LE(acc.max_ulp, derived_bound_ulps(moved));
    }
  }
  Scene other = *make_builtin_scene("patch144");
  EXPECT_THROW(strategy_->update_control_points(other), std::invalid_argument);
}

// Degrees up to 15 (Capabilities::max_degree): the degree-N workload's 16x16 net.
TEST_F(VkBezierTest, HighDegreesMatchTheReference) {
  EXPECT_EQ(find_strategy("vk-bezier")->capabilities().max_degree, 15);
  for (int degree : {10, 15}) {
    const Scene scene = workload_scene(degree, 16, 16, 1);
    const EvalResult result = run(*strategy_, scene, grid(33, 33));
    const Accuracy acc =
        measure_accuracy(scene, result, evaluate_reference(scene, result_samples(result), false));
    std::cout << "vk-bezier degree " << degree << ": max_ulp " << acc.max_ulp << " (bound "
              << derived_bound_ulps(scene) << ")\n";
    EXPECT_EQ(acc.non_finite, 0u);
    EXPECT_LE(acc.max_ulp, derived_bound_ulps(scene)) << degree;
  }
}

TEST_F(VkBezierTest, RefusesWhatItCannotDo) {
  const Scene patch = *make_builtin_scene("patch144");
  EXPECT_THROW(strategy_->prepare(patch, EvalRequest{grid(8, 8), Precision::f64, false}),
               RefusedError);
  Sampling list;
  list.mode = SamplingMode::explicit_list;
  list.explicit_uv = {{{0.5, 0.5}}};
  EXPECT_THROW(strategy_->prepare(patch, EvalRequest{list, Precision::f32, false}), RefusedError);
  const Scene tspline = *make_builtin_scene("tspline-refined");
  EXPECT_THROW(strategy_->prepare(tspline, EvalRequest{grid(8, 8), Precision::f32, false}),
               RefusedError);
}

TEST_F(VkBezierTest, DeviceRecordSaysCpuForASoftwareDevice) {
  const DeviceInfo d = strategy_->device();
  EXPECT_FALSE(d.name.empty());
  if (d.name.find("llvmpipe") != std::string::npos) {
    EXPECT_EQ(d.kind, "cpu");
  }
  const StrategyEntry& entry = *find_strategy("vk-bezier");
  EXPECT_EQ(entry.role, "baseline");
  EXPECT_TRUE(entry.capabilities().updates_control_points);
}

// Domain ends that are not floats (issue 28): every sample finite and on the surface, grid and
// span grid (tests/strategies/domain_ends.h).
TEST_F(VkBezierTest, UnrepresentableDomainEndsStayOnTheSurface) {
  const Scene scene = test::unrepresentable_ends_scene();
  for (const Sampling& sampling : {grid(17, 13), span_grid(5)}) {
    const EvalResult result = run(*strategy_, scene, sampling);
    EXPECT_GT(test::expect_on_surface(scene, result, 64, sampling.label()), 0u);
  }
}

}  // namespace
}  // namespace nurbs
