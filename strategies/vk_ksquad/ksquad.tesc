#version 450
#extension GL_GOOGLE_include_directive : require
// Control stage (003 §4's hull shader): one patch per KSQuad (uniform mode: or per piece of one,
// where a run needs more than maxTessellationGenerationLevel segments).
// Vulkan quads: outer[0] is the edge u = 0 and outer[2] the edge u = 1 (both run along v),
// outer[1] the edge v = 0 and outer[3] the edge v = 1 (along u); inner[0] along u, inner[1]
// along v.
//  * uniform: each edge level is the segment count of that edge's own run of samples (Info-KSQuad
//    table; the run's piece where it was cut), so two patches sharing an edge choose the same
//    level.
//  * adaptive: 003 §3.1's local-area-average test, eq. (3) dist(p(S(corner)), p(S(corner'))) / tau
//    < mu, read per edge: the edge's level tau is the smallest integer with projected length /
//    tau < mu pixels. The paper applies the test to the KSQuad's corner pairs without saying how
//    a level per edge follows; we compute each edge's level from its own two corners only (in a
//    fixed order, from one shared corner table), so the KSQuads on both sides of an edge compute
//    the same float operations on the same data and choose the same level: no cracks. Inner
//    levels are the larger of the two opposite edges' (at least 2, so interior vertices sit on
//    the inner lattice even when both edges are 1).
layout(vertices = 1) out;
layout(constant_id = 0) const int kRaster = 0;  // the render() pipeline (as in ksquad.tese)
#include "ksquad_tables.glsl"

vec2 project(int corner) {
  const vec4 c = mode.view_projection * vec4(corners[corner].xyz, 1.0);
  return c.xy / c.w * 0.5 * mode.viewport;
}

// The level an edge wants (before the cap): +inf when a corner is behind the eye.
float wanted_level(int a, int b) {
  const int first = min(a, b), second = max(a, b);
  const vec4 ca = mode.view_projection * vec4(corners[first].xyz, 1.0);
  const vec4 cb = mode.view_projection * vec4(corners[second].xyz, 1.0);
  if (ca.w <= 0.0 || cb.w <= 0.0) return 1.0 / 0.0;
  return floor(distance(project(first), project(second)) / mode.mu) + 1.0;
}

void main() {
  const int row = PATCH * PATCH_INTS;
  float outer[4];
  if (mode.adaptive == 0) {
    // A run without samples (a grid coarser than the knots) is level 0 (the patch is discarded)
    // when capturing; drawn, its KSQuad still covers its span, as one segment.
    const float level_u = max(float(patches[row + 9]), float(kRaster)),
                level_v = max(float(patches[row + 10]), float(kRaster));
    outer = float[4](level_v, level_u, level_v, level_u);
    gl_TessLevelInner[0] = level_u;
    gl_TessLevelInner[1] = level_v;
  } else {
    const int c00 = patches[row + 12], c10 = patches[row + 13], c01 = patches[row + 14],
              c11 = patches[row + 15];
    const float wanted[4] = float[4](wanted_level(c00, c01), wanted_level(c00, c10),
                                     wanted_level(c10, c11), wanted_level(c01, c11));
    for (int e = 0; e < 4; ++e) {
      outer[e] = min(wanted[e], float(mode.max_level));
      levels[8 * PATCH + e] = outer[e];
      levels[8 * PATCH + 4 + e] = wanted[e];
    }
    gl_TessLevelInner[0] = max(max(outer[1], outer[3]), 2.0);
    gl_TessLevelInner[1] = max(max(outer[0], outer[2]), 2.0);
  }
  for (int e = 0; e < 4; ++e) gl_TessLevelOuter[e] = outer[e];
}
