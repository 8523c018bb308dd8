// The deforming-surface check shared by the GL strategies' tests (000 §5: for a deforming surface
// "only the control points" are sent again). A strategy prepared on frame 0 of the deforming wave
// (scenes/deforming.h) and updated to frame 5 must give, float for float, what a fresh prepare on
// frame 5 gives -- positions and trim masks -- so the update left nothing of frame 0 behind and
// kept everything prepare() would have rebuilt; and it must have moved the result (frame 0's
// points are not frame 5's), within `budget_ulp` of frame 5's reference.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "harness/metrics.h"
#include "harness/runner.h"
#include "scenes/deforming.h"
#include "strategies/registry.h"

namespace nurbs {

// The cases both GL strategies' update tests run: one surface on a grid, a trimmed one on a span
// grid (its trim textures stay from prepare), many surfaces tiled (or paged) at `many_tile`.
struct GlUpdateCase {
  const char* scene;
  Sampling sampling;
  std::string tile;  // "" : the strategy's default
};
inline std::vector<GlUpdateCase> gl_update_cases(const std::string& many_tile) {
  Sampling grid;
  grid.grid_u = 30;
  grid.grid_v = 17;
  Sampling span;
  span.mode = SamplingMode::span_grid;
  span.span_steps = 3;
  return {{"patch144", grid, ""}, {"trimmed-plate", span, ""}, {"many-16", grid, many_tile}};
}

// Returns the updated strategy's record after the update, for the caller's own checks.
inline DeviceInfo expect_update_equals_fresh_prepare(const StrategyEntry& entry,
                                                     const StrategyOptions& options,
                                                     const Scene& base, const Sampling& sampling,
                                                     double budget_ulp) {
  const Scene frame0 = deformed_scene(base, 0), frame5 = deformed_scene(base, 5);
  const EvalRequest request{sampling, Precision::f32, false};
  auto run = [](Strategy& s) {
    s.evaluate();
    s.classify();
    return s.read_back();
  };
  auto updated = entry.create(options);
  updated->prepare(frame0, request);
  const EvalResult before = run(*updated);
  updated->update_control_points(frame5);
  const EvalResult moved = run(*updated);
  auto fresh = entry.create(options);
  fresh->prepare(frame5, request);
  const EvalResult expected = run(*fresh);

  EXPECT_EQ(moved.surfaces.size(), expected.surfaces.size());
  bool any_moved = false;
  for (std::size_t i = 0; i < moved.surfaces.size() && i < expected.surfaces.size(); ++i) {
    const SurfaceResult &m = moved.surfaces[i], &e = expected.surfaces[i];
    EXPECT_EQ(m.positions.size(), e.positions.size()) << "surface " << i;
    if (m.positions.size() != e.positions.size()) continue;
    const std::size_t bytes = m.positions.size() * 3 * sizeof(float);
    EXPECT_EQ(std::memcmp(m.positions.f32(), e.positions.f32(), bytes), 0)
        << "surface " << i << ": the updated net's points differ from a fresh prepare's";
    any_moved =
        any_moved || std::memcmp(m.positions.f32(), before.surfaces[i].positions.f32(), bytes) != 0;
    EXPECT_EQ(m.inside, e.inside) << "surface " << i << ": trim mask";
    EXPECT_EQ(m.inside.empty(), !base.surfaces[i].trim.has_value()) << "surface " << i;
  }
  EXPECT_TRUE(any_moved) << "the update did not move the result";
  const Accuracy accuracy = measure_accuracy(
      frame5, moved, evaluate_reference(frame5, sample_parameters(frame5, sampling), false));
  EXPECT_EQ(accuracy.non_finite, 0u);
  EXPECT_LE(accuracy.max_ulp, budget_ulp);
  return updated->device();
}

}  // namespace nurbs
