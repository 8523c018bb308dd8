// vk-ksquad on the Vulkan device (lavapipe here): accuracy on every built-in scene at its own
// (u, v), pipeline statistics against the levels it chose, cutting past the tessellator's cap,
// control-point updates and the device record.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <tuple>

#include "harness/metrics.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"
#include "tests/reference/test_support.h"

namespace nurbs {
namespace {

using test::grid;
using test::span_grid;

std::unique_ptr<Strategy> adaptive_strategy(const std::string& eye, const std::string& center,
                                            const std::string& mu,
                                            const std::string& max_level = "",
                                            const std::string& pieces = "");

// Span grid T: the tessellator chooses the samples (003 §4), so they are its lattice -- in every
// non-empty span [x_i, x_i+1], x_i + k (x_i+1 - x_i) / T for k = 0..T, computed here in double --
// to the tessellator's precision, the span's ends exactly the knots as floats. Lavapipe's
// tessellator (Mesa's port of the D3D11 reference tessellator) steps from the nearer end of an
// edge by 1 / level rounded to 16.16 fixed point, so vertex k is off k / level by up to about
// min(k, level - k) 2^-17 (measured at T = 100, cut into two patches of level 50: 5e-5 of the
// span at the middle); the bound is twice that plus float rounding.
void expect_span_grid_lattice(const Scene& scene, int steps,
                              const std::vector<SurfaceSamples>& produced) {
  ASSERT_EQ(produced.size(), scene.surfaces.size());
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    const SurfaceSamples& p = produced[i];
    ASSERT_TRUE(p.tensor) << "surface " << i << ": one u per lattice column expected";
    for (int direction = 0; direction < 2; ++direction) {
      const std::vector<double>& knots = direction == 0 ? s.knots_u : s.knots_v;
      const int degree = direction == 0 ? s.degree_u : s.degree_v;
      const int count = direction == 0 ? s.count_u : s.count_v;
      const std::vector<double>& got = direction == 0 ? p.u : p.v;
      const double scale = std::max(std::abs(knots[degree]), std::abs(knots[count]));
      std::size_t k = 0;
      for (int span = degree; span < count; ++span) {
        if (!(knots[span] < knots[span + 1])) continue;
        for (int step = 0; step <= steps; ++step, ++k) {
          ASSERT_LT(k, got.size());
          const double want = step == steps
                                  ? knots[span + 1]
                                  : knots[span] + (knots[span + 1] - knots[span]) * step / steps;
          if (step == 0 || step == steps)
            EXPECT_EQ(got[k], static_cast<float>(want)) << "surface " << i << " knot";
          else
            EXPECT_LE(std::abs(got[k] - want), (std::min(step, steps - step) + 1) * 0x1p-16 *
                                                       (knots[span + 1] - knots[span]) +
                                                   4 * FLT_EPSILON * scale)
                << "surface " << i << " direction " << direction << " span " << span << " step "
                << step;
        }
      }
      EXPECT_EQ(k, got.size());
    }
  }
}

Accuracy run(Strategy& strategy, const Scene& scene, const Sampling& sampling,
             bool normals = false) {
  strategy.prepare(scene, EvalRequest{sampling, Precision::f32, normals});
  strategy.evaluate();
  const EvalResult result = strategy.read_back();
  const auto samples = sample_parameters(scene, sampling);
  const auto produced = result_samples(result);
  if (sampling.mode == SamplingMode::span_grid)
    expect_span_grid_lattice(scene, sampling.span_steps, produced);
  else
    EXPECT_TRUE(same_samples(produced, samples));
  return measure_accuracy(scene, result, evaluate_reference(scene, produced, normals));
}

class VkKsquadTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const Availability a = find_strategy("vk-ksquad")->probe();
    if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
    strategy_ = make_vk_ksquad(StrategyOptions{});
  }
  std::unique_ptr<Strategy> strategy_;
};

// The gate: within 64 float32 ulps of the reference at the strategy's own (u, v) on every
// built-in scene, normals within 1 degree; the worst case per scene is printed (docs/strategies.md
// / results/gates.json quote it).
TEST_F(VkKsquadTest, WithinBudgetOnEveryBuiltinScene) {
  for (const BuiltinSceneInfo& info : builtin_scenes()) {
    if (info.name == "many-4096") continue;  // the default scene list leaves it out too
    const Scene scene = *make_builtin_scene(info.name);
    // A NURBS strategy: the T-spline scenes are refused (tests/tspline checks that).
    if (scene.surfaces.front().is_tspline()) continue;
    SCOPED_TRACE(info.name);
    for (const Sampling& sampling : {span_grid(16), grid(64, 64)}) {
      Accuracy acc;
      try {
        acc = run(*strategy_, scene, sampling, true);
      } catch (const RefusedError& e) {
        // A device limit (maxStorageBufferRange for the output) is a refusal, never a
        // truncation; only the largest span grids meet it.
        EXPECT_EQ(sampling.mode, SamplingMode::span_grid) << info.name << ": " << e.what();
        std::cout << "vk-ksquad " << info.name << " " << sampling.label()
                  << ": refused: " << e.what() << "\n";
        continue;
      }
      EXPECT_EQ(acc.non_finite, 0u) << info.name;
      EXPECT_LE(acc.max_ulp, 64.0)
          << info.name << " " << sampling.label() << ": worst at surface " << acc.worst_surface
          << " u=" << acc.worst_u << " v=" << acc.worst_v;
      ASSERT_TRUE(acc.max_normal_angle_deg.has_value());
      EXPECT_LE(*acc.max_normal_angle_deg, 1.0) << info.name << " " << sampling.label();
      std::cout << "vk-ksquad " << info.name << " " << sampling.label() << ": max_ulp "
                << acc.max_ulp << " (surface " << acc.worst_surface << " u=" << acc.worst_u
                << " v=" << acc.worst_v << "), normals " << *acc.max_normal_angle_deg << " deg\n";
    }
  }
}

// TES invocations (pipeline statistics) = KSDice evaluated = what the chosen levels imply;
// TCS patches = rows of the Info-KSQuad table.
TEST_F(VkKsquadTest, PipelineStatisticsMatchTheChosenLevels) {
  for (const auto& [scene_name, sampling] :
       {std::pair{"patch144", span_grid(8)}, std::pair{"teapot", span_grid(3)},
        std::pair{"tan16", grid(33, 29)}, std::pair{"degree-9", span_grid(5)}}) {
    const Scene scene = *make_builtin_scene(scene_name);
    strategy_->prepare(scene, EvalRequest{sampling, Precision::f32, false});
    strategy_->evaluate();
    const KsquadStatistics st = ksquad_statistics(*strategy_);
    EXPECT_GT(st.patches_drawn, 0u);
    EXPECT_EQ(st.control_patches, st.patches_drawn) << scene_name;
    EXPECT_EQ(st.evaluation_invocations, st.implied_vertices) << scene_name;
    std::cout << scene_name << " " << sampling.label() << ": " << st.patches_drawn << " patches, "
              << st.evaluation_invocations << " TES invocations\n";
  }
}

// Span grid T = 16 on patch144: one patch per KSQuad, (T+1)^2 vertices each (DESIGN's span grid).
TEST_F(VkKsquadTest, SpanGridIsOnePatchPerKsquadWithTheLattice) {
  const Scene scene = *make_builtin_scene("patch144");
  strategy_->prepare(scene, EvalRequest{span_grid(16), Precision::f32, false});
  strategy_->evaluate();
  const KsquadStatistics st = ksquad_statistics(*strategy_);
  const Surface& s = scene.surfaces[0];
  std::uint64_t spans_u = 0, spans_v = 0;
  for (int i = s.degree_u; i < s.count_u; ++i) spans_u += s.knots_u[i] < s.knots_u[i + 1];
  for (int j = s.degree_v; j < s.count_v; ++j) spans_v += s.knots_v[j] < s.knots_v[j + 1];
  EXPECT_EQ(st.patches_drawn, spans_u * spans_v);
  EXPECT_LE(st.patches_drawn,
            static_cast<std::uint64_t>((s.count_u - s.degree_u) * (s.count_v - s.degree_v)));
  EXPECT_EQ(st.evaluation_invocations, st.patches_drawn * 17 * 17);
  EXPECT_EQ(st.max_level, 16);
}

// T past maxTessellationGenerationLevel: each KSQuad is cut into several patches, levels within
// the cap, every sample still evaluated and as accurate.
TEST_F(VkKsquadTest, LevelsPastTheCapAreCutNotClamped) {
  for (const char* scene_name : {"patch144", "degree-9"}) {
    const Scene scene = *make_builtin_scene(scene_name);
    strategy_->prepare(scene, EvalRequest{span_grid(100), Precision::f32, false});
    const KsquadStatistics before = ksquad_statistics(*strategy_);
    ASSERT_GT(before.level_cap, 0);
    ASSERT_LT(before.level_cap, 100) << "the device's cap is no test of cutting";
    const Accuracy acc = run(*strategy_, scene, span_grid(100));
    const KsquadStatistics st = ksquad_statistics(*strategy_);
    EXPECT_LE(st.max_level, st.level_cap);
    EXPECT_EQ(st.evaluation_invocations, st.implied_vertices);
    EXPECT_EQ(acc.non_finite, 0u);
    EXPECT_LE(acc.max_ulp, 64.0) << scene_name;
    std::cout << scene_name << " span100: " << st.patches_drawn << " patches (cap " << st.level_cap
              << "), max_ulp " << acc.max_ulp << "\n";
  }
}

// update_control_points re-uploads only the points: the result is the moved surface's.
TEST_F(VkKsquadTest, UpdateControlPointsEvaluatesTheMovedNet) {
  Scene scene = *make_builtin_scene("teapot");
  const Sampling sampling = span_grid(4);
  strategy_->prepare(scene, EvalRequest{sampling, Precision::f32, false});
  for (Surface& s : scene.surfaces)
    for (auto& p : s.points) p[2] += 0.25 * p[0];
  strategy_->update_control_points(scene);
  strategy_->evaluate();
  const EvalResult result = strategy_->read_back();
  const Accuracy acc = measure_accuracy(
      scene, result, evaluate_reference(scene, sample_parameters(scene, sampling), false));
  EXPECT_LE(acc.max_ulp, 64.0);
}

TEST_F(VkKsquadTest, DeviceRecordSaysCpuForASoftwareDevice) {
  const DeviceInfo d = strategy_->device();
  EXPECT_FALSE(d.name.empty());
  if (d.name.find("llvmpipe") != std::string::npos) {
    EXPECT_EQ(d.kind, "cpu");
  }
  EXPECT_EQ(d.details.count("max_tessellation_generation_level"), 1u);
}

TEST_F(VkKsquadTest, DeviceOutOfRangeIsAnError) {
  StrategyOptions options;
  options.extra["device"] = "99";
  EXPECT_THROW(make_vk_ksquad(options), std::runtime_error);
}

TEST_F(VkKsquadTest, RefusesWhatItCannotDo) {
  const Scene scene = *make_builtin_scene("patch144");
  EXPECT_THROW(strategy_->prepare(scene, EvalRequest{grid(8, 8), Precision::f64, false}),
               RefusedError);
}

// Adaptive mode (003 §3.1): a close camera so the levels vary over the surface.
std::unique_ptr<Strategy> adaptive_strategy(const std::string& eye, const std::string& center,
                                            const std::string& mu, const std::string& max_level,
                                            const std::string& pieces) {
  StrategyOptions options;
  options.extra = {{"vk-mode", "adaptive"},     {"vk-eye", eye},
                   {"vk-center", center},       {"vk-mu", mu},
                   {"vk-max-level", max_level}, {"vk-pieces", pieces}};
  return make_vk_ksquad(options);
}

struct AdaptiveCase {
  const char* scene;
  const char* eye;
  const char* center;
  const char* mu;
  const char* max_level = "";
  const char* pieces = "";
};
// The last: levels up to 34 with the tessellator capped at 16, so KSQuads are cut into up to
// three pieces per direction (ksquad.tesc), not capped.
const AdaptiveCase kAdaptiveCases[] = {{"patch144", "", "", "4"},
                                       {"torus", "", "", "8"},
                                       {"tan16", "", "", "4"},
                                       {"patch144", "", "", "4", "16", "4"}};

TEST_F(VkKsquadTest, AdaptiveStatisticsMatchTheChosenLevels) {
  for (const AdaptiveCase& c : kAdaptiveCases) {
    auto strategy = adaptive_strategy(c.eye, c.center, c.mu, c.max_level, c.pieces);
    const Scene scene = *make_builtin_scene(c.scene);
    strategy->prepare(scene, EvalRequest{span_grid(1), Precision::f32, false});
    strategy->evaluate();
    const KsquadStatistics st = ksquad_statistics(*strategy);
    EXPECT_EQ(st.control_patches, st.patches_drawn) << c.scene;
    EXPECT_EQ(st.evaluation_invocations, st.implied_vertices) << c.scene;
    EXPECT_EQ(st.capped_edges, 0u) << c.scene;
    EXPECT_LE(st.max_level, st.level_cap) << c.scene;
    std::cout << c.scene << " adaptive: " << st.patches_drawn << " patches, max level "
              << st.max_level << ", " << st.evaluation_invocations << " TES invocations\n";
  }
}

// At the (u, v) it chose, adaptive mode is as accurate as uniform mode, normals included.
TEST_F(VkKsquadTest, AdaptiveWithinBudgetAtItsOwnSamples) {
  for (const AdaptiveCase& c : kAdaptiveCases) {
    auto strategy = adaptive_strategy(c.eye, c.center, c.mu, c.max_level, c.pieces);
    const Scene scene = *make_builtin_scene(c.scene);
    strategy->prepare(scene, EvalRequest{span_grid(1), Precision::f32, true});
    strategy->evaluate();
    const EvalResult result = strategy->read_back();
    const auto produced = result_samples(result);
    ASSERT_GT(total_samples(produced), 0u);
    const Accuracy acc = measure_accuracy(scene, result, evaluate_reference(scene, produced, true));
    EXPECT_EQ(acc.non_finite, 0u);
    EXPECT_LE(acc.max_ulp, 64.0) << c.scene;
    ASSERT_TRUE(acc.max_normal_angle_deg.has_value());
    EXPECT_LE(*acc.max_normal_angle_deg, 1.0) << c.scene;
    std::cout << c.scene << " adaptive: " << total_samples(produced) << " vertices, max_ulp "
              << acc.max_ulp << ", normals " << *acc.max_normal_angle_deg << " deg\n";
  }
}

// No cracks: every vertex on an edge shared by two KSQuads of a surface coincides with a vertex
// of the neighbour's copy of that edge -- same (u, v), positions within a few float ulps (each
// side evaluates with its own span's basis) -- and both sides hold the same number of vertices.
TEST_F(VkKsquadTest, AdaptiveMeshHasNoCracksBetweenKsquads) {
  for (const AdaptiveCase& c : kAdaptiveCases) {
    auto strategy = adaptive_strategy(c.eye, c.center, c.mu, c.max_level, c.pieces);
    const Scene scene = *make_builtin_scene(c.scene);
    strategy->prepare(scene, EvalRequest{span_grid(1), Precision::f32, false});
    strategy->evaluate();
    double largest = 0;
    for (const Surface& s : scene.surfaces)
      for (const auto& p : s.points)
        for (double x : p) largest = std::max(largest, std::abs(x));
    const double tolerance = 16 * FLT_EPSILON * largest;
    std::map<std::tuple<int, int, float, float, float>, std::vector<const CapturedEdge*>> shared;
    const std::vector<CapturedEdge> edges = ksquad_captured_edges(*strategy);
    for (const CapturedEdge& e : edges)
      shared[{e.surface, e.direction, e.fixed, e.lo, e.hi}].push_back(&e);
    int checked = 0, levels_differ = 0;
    double worst = 0;
    std::set<std::size_t> sizes;
    for (const auto& [key, pair] : shared) {
      if (pair.size() != 2) continue;  // a surface boundary edge
      ++checked;
      const auto& a = pair[0]->vertices;
      const auto& b = pair[1]->vertices;
      EXPECT_EQ(a.size(), b.size()) << c.scene << ": the two sides chose different levels";
      sizes.insert(a.size());
      for (const auto& va : a) {
        double best = 1e300;
        for (const auto& vb : b)
          if (std::abs(va[0] - vb[0]) <= 1e-6f && std::abs(va[1] - vb[1]) <= 1e-6f)
            best = std::min<double>(best, std::hypot(va[2] - vb[2], va[3] - vb[3], va[4] - vb[4]));
        EXPECT_LE(best, tolerance) << c.scene << ": vertex (" << va[0] << ", " << va[1]
                                   << ") has no partner on the neighbour's edge";
        worst = std::max(worst, best);
      }
    }
    levels_differ = static_cast<int>(sizes.size());
    EXPECT_GT(checked, 0) << c.scene;
    EXPECT_GT(levels_differ, 1) << c.scene << ": the camera should make the levels vary";
    std::cout << c.scene << " adaptive: " << checked << " shared edges, " << levels_differ
              << " distinct levels, worst partner distance " << worst << " (tolerance " << tolerance
              << ")\n";
  }
}

TEST_F(VkKsquadTest, AdaptiveOptionsAreChecked) {
  StrategyOptions options;
  options.extra = {{"vk-mode", "sometimes"}};
  EXPECT_THROW(make_vk_ksquad(options), std::invalid_argument);
  options.extra = {{"vk-mode", "adaptive"}, {"vk-eye", "1,2"}};
  EXPECT_THROW(make_vk_ksquad(options), std::invalid_argument);
  options.extra = {{"vk-mode", "adaptive"}, {"vk-max-level", "100000"}};
  EXPECT_THROW(make_vk_ksquad(options), std::invalid_argument);
}

// Draws bounded by vk-vertices-per-draw (one patch each at 1) evaluate exactly what one draw per
// degree pair does: each draw's patch_base finds its own rows of the Info-KSQuad table.
TEST_F(VkKsquadTest, DrawsSplitByVertexBudgetGiveTheSameSamples) {
  const Scene scene = *make_builtin_scene("many-16");
  const EvalRequest request{span_grid(4), Precision::f32, false};
  std::vector<EvalResult> results;
  std::vector<std::string> draws;
  std::uint64_t patches = 0;
  for (const char* budget : {"0", "1"}) {
    StrategyOptions options;
    options.extra = {{"vk-vertices-per-draw", budget}};
    std::unique_ptr<Strategy> strategy = make_vk_ksquad(options);
    strategy->prepare(scene, request);
    strategy->evaluate();
    results.push_back(strategy->read_back());
    draws.push_back(strategy->device().details.at("draws"));
    patches = ksquad_statistics(*strategy).patches_drawn;
  }
  EXPECT_EQ(draws[0], "1");  // many-16: bicubic patches only, one degree pair
  EXPECT_EQ(patches, 16u);
  EXPECT_EQ(draws[1], std::to_string(patches));
  ASSERT_EQ(results[0].surfaces.size(), results[1].surfaces.size());
  for (std::size_t k = 0; k < results[0].surfaces.size(); ++k) {
    const PointArray &one_draw = results[0].surfaces[k].positions,
                     &split = results[1].surfaces[k].positions;
    ASSERT_EQ(one_draw.size(), split.size());
    for (std::size_t i = 0; i < one_draw.size(); ++i)
      ASSERT_EQ(one_draw[i], split[i]) << "surface " << k << ", sample " << i;
  }
  StrategyOptions bad;
  bad.extra = {{"vk-vertices-per-draw", "-3"}};
  EXPECT_THROW(make_vk_ksquad(bad), std::invalid_argument);
}

// render(): the patches drawn with rasterization into the offscreen image, in both modes.
TEST_F(VkKsquadTest, RenderDrawsTheSurfaceOffscreen) {
  const Scene scene = *make_builtin_scene("teapot");
  strategy_->prepare(scene, EvalRequest{span_grid(8), Precision::f32, false});
  EXPECT_EQ(ksquad_rendered_pixels(*strategy_), 0u);  // nothing drawn yet
  ASSERT_TRUE(ksquad_render(*strategy_));
  const std::size_t covered = ksquad_rendered_pixels(*strategy_);
  // The default camera fits the scene's bounding sphere into a 1024x768 image: the teapot
  // covers a good part of it, and not all of it.
  EXPECT_GT(covered, 1024u * 768u / 20);
  EXPECT_LT(covered, 1024u * 768u);
  auto adaptive = adaptive_strategy("", "", "4");
  adaptive->prepare(scene, EvalRequest{span_grid(1), Precision::f32, false});
  ASSERT_TRUE(ksquad_render(*adaptive));
  const std::size_t adaptive_covered = ksquad_rendered_pixels(*adaptive);
  EXPECT_NEAR(static_cast<double>(adaptive_covered), static_cast<double>(covered),
              0.05 * static_cast<double>(covered));
  std::cout << "teapot render: " << covered << " pixels (uniform span8), " << adaptive_covered
            << " (adaptive)\n";
}

}  // namespace
}  // namespace nurbs

namespace nurbs {
namespace {

std::unique_ptr<Strategy> gs_strategy() {
  StrategyOptions options;
  options.extra = {{"vk-mode", "gs"}};
  return make_vk_ksquad(options);
}

// 003 §4's GS-based mapping (ksquad.geom): the geometry stage generates each KSQuad's span-grid
// lattice itself; as accurate as the tessellator mappings at its own samples, normals included.
TEST_F(VkKsquadTest, GsMappingWithinBudgetOnItsLattice) {
  auto gs = gs_strategy();
  EXPECT_EQ(gs->device().details.at("vk_mode"), "gs");
  for (const char* scene_name : {"patch144", "teapot", "torus", "degree-9"}) {
    const Scene scene = *make_builtin_scene(scene_name);
    const Accuracy acc = run(*gs, scene, span_grid(8), true);
    EXPECT_EQ(acc.non_finite, 0u) << scene_name;
    EXPECT_LE(acc.max_ulp, 64.0) << scene_name;
    ASSERT_TRUE(acc.max_normal_angle_deg.has_value());
    EXPECT_LE(*acc.max_normal_angle_deg, 1.0) << scene_name;
    std::cout << scene_name << " gs span8: max_ulp " << acc.max_ulp << ", normals "
              << *acc.max_normal_angle_deg << " deg\n";
  }
}

// The bound 003 §4 gives for this mapping: a KSQuad's KSDice must fit one invocation's output,
// so past span grid 8 (144 vertices of 7 components: ksquad.geom) it refuses, as it does grids.
TEST_F(VkKsquadTest, GsMappingRefusesWhatOneInvocationCannotEmit) {
  auto gs = gs_strategy();
  const Scene scene = *make_builtin_scene("patch144");
  EXPECT_THROW(gs->prepare(scene, EvalRequest{span_grid(9), Precision::f32, false}), RefusedError);
  EXPECT_THROW(gs->prepare(scene, EvalRequest{grid(16, 16), Precision::f32, false}), RefusedError);
}

// render(): the GS mapping's triangle strips cover what the tessellator's lattice covers (the
// same vertices, triangulated differently along the diagonals).
TEST_F(VkKsquadTest, GsRenderCoversWhatTheTessellatorCovers) {
  const Scene scene = *make_builtin_scene("teapot");
  const EvalRequest request{span_grid(8), Precision::f32, false};
  auto gs = gs_strategy();
  gs->prepare(scene, request);
  ASSERT_TRUE(ksquad_render(*gs));
  strategy_->prepare(scene, request);
  ASSERT_TRUE(ksquad_render(*strategy_));
  const double by_gs = static_cast<double>(ksquad_rendered_pixels(*gs));
  const double by_tessellator = static_cast<double>(ksquad_rendered_pixels(*strategy_));
  EXPECT_GT(by_gs, 1024.0 * 768 / 20);
  EXPECT_NEAR(by_gs, by_tessellator, 0.005 * by_tessellator);
  std::cout << "teapot span8 render: " << by_gs << " pixels (gs), " << by_tessellator
            << " (tessellator)\n";
}

}  // namespace
}  // namespace nurbs
