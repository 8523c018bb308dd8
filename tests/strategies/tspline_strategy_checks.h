// Helpers shared by the T-spline strategies' tests (cl-tspline-bezier, cpu-tspline-bezier): a
// scene of one T-spline, the random samplings they run, one prepare/evaluate/read back, bitwise
// comparison of results, the update check and the T-splines-only refusal.
#pragma once

#include <gtest/gtest.h>

#include <cfloat>
#include <cstring>
#include <string>
#include <vector>

#include "reference/tspline.h"
#include "scenes/builtin_scenes.h"
#include "scenes/deforming.h"
#include "strategies/registry.h"
#include "tests/reference/random_nurbs.h"

namespace nurbs::test {

inline double unit_roundoff(Precision precision) {
  return precision == Precision::f32 ? FLT_EPSILON / 2 : DBL_EPSILON / 2;
}

inline Scene tspline_scene(TSplineSurface t) {
  Scene scene;
  scene.name = t.name;
  scene.surfaces.push_back(make_tspline_surface(std::move(t)));
  return scene;
}

// A span grid of `span_steps` steps (every break and cell interior) and an explicit list of
// `list_size` random parameters per surface, plus the domain corners.
inline std::vector<Sampling> span_and_list_samplings(Rng& rng, const Scene& scene, int span_steps,
                                                     int list_size) {
  Sampling span;
  span.mode = SamplingMode::span_grid;
  span.span_steps = span_steps;
  Sampling list;
  list.mode = SamplingMode::explicit_list;
  for (const Surface& s : scene.surfaces) {
    std::vector<std::array<double, 2>> uv{{s.u_min(), s.v_min()}, {s.u_max(), s.v_max()}};
    for (int k = 0; k < list_size; ++k)
      uv.push_back(
          {uniform_real(rng, s.u_min(), s.u_max()), uniform_real(rng, s.v_min(), s.v_max())});
    list.explicit_uv.push_back(uv);
  }
  return {span, list};
}

inline EvalResult evaluate(Strategy& strategy, const Scene& scene, const EvalRequest& request) {
  strategy.prepare(scene, request);
  strategy.evaluate();
  return strategy.read_back();
}

inline bool same_bits(const PointArray& a, const PointArray& b) {
  if (a.size() != b.size() || a.precision() != b.precision()) return false;
  const std::size_t bytes = a.size() * 3 * (a.precision() == Precision::f32 ? 4 : 8);
  return a.precision() == Precision::f32 ? std::memcmp(a.f32(), b.f32(), bytes) == 0
                                         : std::memcmp(a.f64(), b.f64(), bytes) == 0;
}

// `updated` prepared on frame 0 of the deforming wave (scenes/deforming.h) of the one-surface
// scene `base`, updated to frame 7 (update_control_points) and evaluated gives, bit for bit, what
// `fresh`'s prepare() on frame 7 gives, positions and normals, and not frame 0's result (an update
// that does nothing fails). Returns `fresh`'s result.
inline EvalResult expect_update_equals_fresh_prepare(Strategy& updated, Strategy& fresh,
                                                     const Scene& base,
                                                     const EvalRequest& request) {
  const EvalResult before = evaluate(updated, deformed_scene(base, 0), request);
  const Scene moved = deformed_scene(base, 7);
  updated.update_control_points(moved);
  updated.evaluate();
  const EvalResult after = updated.read_back();
  EvalResult expected = evaluate(fresh, moved, request);
  EXPECT_EQ(after.surfaces.size(), 1u);
  if (after.surfaces.size() != 1 || expected.surfaces.size() != 1) return expected;
  EXPECT_TRUE(same_bits(after.surfaces[0].positions, expected.surfaces[0].positions));
  EXPECT_TRUE(same_bits(after.surfaces[0].normals, expected.surfaces[0].normals));
  EXPECT_FALSE(same_bits(after.surfaces[0].positions, before.surfaces[0].positions));
  return expected;
}

// T-splines only: a NURBS scene is refused, by the harness's rule and by prepare().
inline void expect_nurbs_scenes_refused(const StrategyEntry& entry) {
  const Scene nurbs = *make_builtin_scene("patch144");
  const EvalRequest request{Sampling{}, Precision::f32, false};
  const auto reason = refusal_reason(entry.capabilities(), nurbs, request);
  ASSERT_TRUE(reason.has_value());
  EXPECT_NE(reason->find("T-splines only"), std::string::npos) << *reason;
  const auto strategy = entry.create(StrategyOptions{});
  EXPECT_THROW(strategy->prepare(nurbs, request), RefusedError);
}

}  // namespace nurbs::test
