// vk-ksquad's strategy object, for tests that look past the Strategy contract (pipeline
// statistics, the captured mesh). Vulkan builds only; the harness uses vk_ksquad_entry().
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "strategies/strategy.h"

namespace nurbs {

// The last evaluate(): what the pipeline statistics counted and what the chosen levels imply.
struct KsquadStatistics {
  std::uint64_t patches_drawn = 0;           // rows of the Info-KSQuad table
  std::uint64_t control_patches = 0;         // pipeline statistics: TCS patches
  std::uint64_t evaluation_invocations = 0;  // pipeline statistics: TES invocations (KSDice)
  std::uint64_t implied_vertices = 0;        // sum over patches of the levels' vertex count
  int max_level = 0;                         // largest level set
  int level_cap = 0;  // per patch. uniform: maxTessellationGenerationLevel; adaptive: vk-max-level
  std::uint64_t capped_edges = 0;  // adaptive: KSQuad edges past vk-pieces x level_cap
  // Adaptive and nonuniform: KSQuad edges inside a surface (two KSQuads share them), and those of
  // them whose two sides chose different segment counts -- T-junctions, so cracks wherever the
  // surface bends (adaptive: the KSQuad edge's level; nonuniform: its lattice's, before the
  // geometry stage subdivides); 0 cracked under vk-eq3=edge in adaptive mode.
  std::uint64_t shared_edges = 0, cracked_edges = 0;
  // Adaptive: triangles the tessellator makes for the levels set (nonuniform: emitted, below).
  std::uint64_t tessellated_triangles = 0;
  // Nonuniform mode (the geometry stage's records): KSDice the tessellator started, those
  // subdivided by the linear-approximation test (003 eq. 4) and by the boundary-region test (eq.
  // 5), those culled (Exact Visible Set: view frustum, back face), triangles emitted.
  std::uint64_t ksdice = 0, subdivided_linear = 0, subdivided_boundary = 0, culled_frustum = 0,
                culled_back = 0, triangles = 0;
};

// Nonuniform mode, after evaluate(): one geometry-stage record per KSDie (i, j) of a KSQuad's
// level_u x level_v lattice. status: 1 emitted, 2 culled by the view frustum, 3 culled as a back
// face; the depths of eq. 4 and eq. 5 (-1 when culled), the f tag (bit e: side e -- u = lo, v = lo,
// u = hi, v = hi -- on a surface boundary shared with a surface that is not a friend).
struct KsdieRecord {
  int surface = 0, span_u = 0, span_v = 0, i = 0, j = 0, level_u = 0, level_v = 0;
  int status = 0, depth_linear = 0, depth_boundary = 0, f = 0;
};

// Adaptive mode: the captured vertices (u, v, x, y, z) of one outer edge of one KSQuad, keyed by
// the edge: `direction` 0 = u fixed at `fixed`, v in [lo, hi]; 1 = v fixed, u in [lo, hi].
struct CapturedEdge {
  int surface = 0, direction = 0;
  float fixed = 0, lo = 0, hi = 0;
  std::vector<std::array<float, 5>> vertices;
};

// Adaptive mode, after evaluate(): per patch, the levels its control stage set and wanted (003
// eq. 3, before the cap) for its four outer edges, read back from the control stage's storage
// buffer. Edges in the order u = x_i, v = y_j, u = x_i+1, v = y_j+1 of KSQuad (span_u, span_v).
struct PatchLevels {
  int surface = 0, span_u = 0, span_v = 0;
  std::array<float, 4> set{}, wanted{};
};

std::unique_ptr<Strategy> make_vk_ksquad(const StrategyOptions& options);
// `strategy` must come from make_vk_ksquad; throws std::invalid_argument otherwise.
KsquadStatistics ksquad_statistics(const Strategy& strategy);
// After evaluate() in adaptive mode (empty in uniform mode).
std::vector<CapturedEdge> ksquad_captured_edges(const Strategy& strategy);
// After evaluate() in adaptive mode (empty in uniform mode).
std::vector<PatchLevels> ksquad_patch_levels(const Strategy& strategy);
// After evaluate() in nonuniform mode (empty otherwise).
std::vector<KsdieRecord> ksquad_ksdice(const Strategy& strategy);
// Draws the prepared patches into the offscreen image (003 §4 end to end; timed as `render`
// where the runner has that phase); the pixels the last render() covered.
bool ksquad_render(Strategy& strategy);
std::size_t ksquad_rendered_pixels(const Strategy& strategy);

}  // namespace nurbs
