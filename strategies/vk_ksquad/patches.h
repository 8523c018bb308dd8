// How vk-ksquad cuts KSQuads into tessellation patches (CPU only, tested without a device).
#pragma once

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "strategies/ksquad/ksquad_table.h"

namespace nurbs::vk_ksquad {

// The tessellator makes at most `max_level` segments per edge (maxTessellationGenerationLevel,
// 64 on lavapipe and most GPUs). A run of `count` samples needs count - 1 segments; past the cap
// it is cut into the fewest pieces of nearly equal length, each piece a sub-range of the run
// sharing its end sample with the next (so neighbouring patches meet on a common edge with the
// same level). Never clamped: every sample of the run is in a piece. A run of one sample is one
// piece of level 1 whose two tessellator ends both land on it.
inline std::vector<ksquad::SpanRun> split_run(const ksquad::SpanRun& run, int max_level) {
  if (run.count <= 1) return {run};
  const int segments = run.count - 1;
  const int pieces = segments / max_level + (segments % max_level != 0);  // no overflow
  std::vector<ksquad::SpanRun> out;
  for (int k = 0; k < pieces; ++k) {
    const int first = k * segments / pieces, last = (k + 1) * segments / pieces;
    out.push_back({run.span, run.begin + first, last - first + 1});
  }
  return out;
}

// Tessellation level of a run: its segment count (a single sample: 1; no sample: 0, a patch the
// tessellator discards).
inline int run_level(const ksquad::SpanRun& run) {
  return run.count == 0 ? 0 : std::max(run.count - 1, 1);
}

// The share [lo, hi] of its run's knot span that a piece of the run (split_run) covers when the
// run's segments divide the span equally -- the span grid's lattice, and how render() draws a
// grid -- as the fractions the evaluation stage blends the span's knots with. A run of at most
// one sample covers the whole span.
inline std::pair<float, float> piece_share(const ksquad::SpanRun& run,
                                           const ksquad::SpanRun& piece) {
  const int segments = run.count - 1;
  if (segments <= 0) return {0.0f, 1.0f};
  const int first = piece.begin - run.begin, last = first + piece.count - 1;
  return {static_cast<float>(static_cast<double>(first) / segments),
          static_cast<float>(static_cast<double>(last) / segments)};
}

// A grid's runs (ksquad::runs_of_grid) with a run of no samples added for every non-empty knot
// span in [knots[degree], knots[count]] that holds none (a grid coarser than the knots): drawn,
// every span needs its patch or the image has a hole there.
inline std::vector<ksquad::SpanRun> with_empty_spans(const std::vector<ksquad::SpanRun>& runs,
                                                     const std::vector<double>& knots, int degree,
                                                     int count) {
  std::vector<ksquad::SpanRun> out;
  std::size_t next = 0;
  for (int span = degree; span < count; ++span) {
    if (!(knots[span] < knots[span + 1])) continue;
    if (next < runs.size() && runs[next].span == span) {
      out.push_back(runs[next++]);
    } else {
      const int begin = next < runs.size()
                            ? runs[next].begin
                            : (runs.empty() ? 0 : runs.back().begin + runs.back().count);
      out.push_back({span, begin, 0});
    }
  }
  return out;
}

// Vertices the Vulkan tessellator generates for a quad patch with outer levels (lv, lu, lv, lu)
// and inner levels (lu, lv), equal spacing (Vulkan spec, "Quad Tessellation"): one quad when the
// first inner and all outer levels are 1; otherwise an inner level of 1 is raised to 2, the
// outer ring holds 2 lu + 2 lv vertices and the inside (i0 - 1)(i1 - 1).
inline std::uint64_t quad_domain_vertices(int lu, int lv) {
  if (lu == 0 || lv == 0) return 0;  // discarded
  if (lu == 1 && lv == 1) return 4;
  const std::uint64_t i0 = std::max(lu, 2), i1 = std::max(lv, 2);
  return 2 * static_cast<std::uint64_t>(lu) + 2 * static_cast<std::uint64_t>(lv) +
         (i0 - 1) * (i1 - 1);
}

}  // namespace nurbs::vk_ksquad
