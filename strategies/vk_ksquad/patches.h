// How vk-ksquad cuts KSQuads into tessellation patches (CPU only, tested without a device).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <tuple>
#include <utility>
#include <vector>

#include "reference/surface.h"
#include "strategies/ksquad/ksquad_table.h"
#include "strategies/vk_ksquad/ksquad_layout.h"

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

// Triangles the Vulkan tessellator makes for a quad patch with outer levels o (o[0], o[2] along
// v, o[1], o[3] along u) and inner levels i0 (along u), i1 (along v), equal spacing (Vulkan spec,
// "Quad Tessellation"): one quad (2 triangles) when the first inner and all outer levels are 1;
// otherwise an inner level of 1 is raised to 2, the inner rectangle holds 2 (i0 - 2)(i1 - 2)
// triangles and the ring between each outer edge of o segments and the inner edge facing it
// (i - 2 segments) o + i - 2.
inline std::uint64_t quad_domain_triangles(const float o[4], int i0, int i1) {
  if (o[0] <= 0 || o[1] <= 0 || o[2] <= 0 || o[3] <= 0) return 0;  // discarded
  if (i0 <= 1 && o[0] == 1 && o[1] == 1 && o[2] == 1 && o[3] == 1) return 2;
  const std::uint64_t a = static_cast<std::uint64_t>(std::max(i0, 2)) - 2,
                      b = static_cast<std::uint64_t>(std::max(i1, 2)) - 2;
  return 2 * a * b + static_cast<std::uint64_t>(o[1] + o[3]) + 2 * a +
         static_cast<std::uint64_t>(o[0] + o[2]) + 2 * b;
}

// One vkCmdDraw: rows [first, first + count) of the patch table, all of one degree pair (the
// evaluation stage's specialization constants: one pipeline per pair).
struct Draw {
  int du = 0, dv = 0;
  std::uint32_t first = 0, count = 0;
};

// The sort key of a patch row (kPatchInts ints, row[0] its surface): its surface's degrees, and
// whether it holds no samples (a level 0).
inline std::tuple<int, int, bool> draw_key(const int* row, const Scene& scene) {
  const Surface& s = scene.surfaces[row[0]];
  return {s.degree_u, s.degree_v, row[kPatchLevelU] == 0 || row[kPatchLevelV] == 0};
}

// Groups the patch table by degree pair, one draw (and one specialised pipeline) each, stably; a
// grid's patches without samples last in their group, drawn by render() only. (Captured with
// level 0 among the others, the patches after them got wrong samples on lavapipe -- tan256 grid
// 64x64: 1e7 ulps -- as if the evaluation stage's gl_PrimitiveID skipped the discarded ones.)
inline void sort_by_degrees(std::vector<int>& patches, const Scene& scene) {
  std::vector<std::array<int, kPatchInts>> rows(patches.size() / kPatchInts);
  for (std::size_t k = 0; k < rows.size(); ++k)
    std::copy_n(&patches[kPatchInts * k], kPatchInts, rows[k].begin());
  std::stable_sort(rows.begin(), rows.end(), [&](const auto& a, const auto& b) {
    return draw_key(a.data(), scene) < draw_key(b.data(), scene);
  });
  for (std::size_t k = 0; k < rows.size(); ++k)
    std::copy(rows[k].begin(), rows[k].end(), &patches[kPatchInts * k]);
}

// The draws of a table sorted by sort_by_degrees: runs of rows of one degree pair, each also
// ended where its vertices would pass `vertices_per_draw` (0: no bound; see
// kDefaultVerticesPerDraw). A patch counts as `fixed_vertices` when non-zero (adaptive: the level
// cap), else as its levels' vertex count. `with_empty`: the rows without samples too (render()).
inline std::vector<Draw> make_draws(const std::vector<int>& patches, const Scene& scene,
                                    bool with_empty, std::uint64_t vertices_per_draw,
                                    std::uint64_t fixed_vertices) {
  std::vector<Draw> draws;
  std::uint64_t draw_vertices = 0;
  for (std::size_t k = 0; k < patches.size() / kPatchInts; ++k) {
    const int* row = &patches[kPatchInts * k];
    const auto [du, dv, empty] = draw_key(row, scene);
    if (empty && !with_empty) continue;
    const std::uint64_t vertices =
        fixed_vertices > 0
            ? fixed_vertices
            : quad_domain_vertices(std::max(row[kPatchLevelU], 1), std::max(row[kPatchLevelV], 1));
    const bool full =
        vertices_per_draw > 0 && draw_vertices > 0 && draw_vertices + vertices > vertices_per_draw;
    if (draws.empty() || draws.back().du != du || draws.back().dv != dv || full ||
        draws.back().first + draws.back().count != k) {
      draws.push_back({du, dv, static_cast<std::uint32_t>(k), 0});
      draw_vertices = 0;
    }
    ++draws.back().count;
    draw_vertices += vertices;
  }
  return draws;
}

}  // namespace nurbs::vk_ksquad
