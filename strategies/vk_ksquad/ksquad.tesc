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
//    the inner lattice even when both edges are 1). This per-edge reading departs from the
//    printed quantifiers "k, m in {i, i+1} and k < m, l, n in {j, j+1} and l < n": read
//    literally they leave the one pair (x_i, y_j)-(x_i+1, y_j+1), the KSQuad's diagonal, and one
//    tau for the whole KSQuad. vk-eq3=literal (mode.eq3_literal) does that -- every edge's level
//    from the diagonal -- so the two readings can be measured against each other (neighbours then
//    choose different levels on a shared edge: cracks, counted by the host).
//    vk-thresholds=surface: mu times the surface's threshold_scale (ksquad_tables.glsl).
layout(vertices = 1) out;
// Adaptive: this patch's corners in its KSQuad's (fu, fv), (0,0) (1,0) (0,1) (1,1) of the
// tessellator's domain; the row of the Info-KSQuad table (the evaluation stage reads it from here:
// its gl_PrimitiveID was seen to skip discarded patches on lavapipe).
layout(location = 0) patch out vec2 piece_corners[4];
layout(location = 4) patch out int patch_row;
layout(constant_id = 0) const int kRaster = 0;  // the render() pipeline (as in ksquad.tese)
#include "ksquad_tables.glsl"

vec2 project(int corner) {
  const vec4 c = mode.view_projection * vec4(corners[corner].xyz, 1.0);
  return c.xy / c.w * 0.5 * mode.viewport;
}

// The level the corner pair (a, b) wants (before the cap): +inf when a corner is behind the eye.
float wanted_level(int a, int b, float mu) {
  const int first = min(a, b), second = max(a, b);
  const vec4 ca = mode.view_projection * vec4(corners[first].xyz, 1.0);
  const vec4 cb = mode.view_projection * vec4(corners[second].xyz, 1.0);
  if (ca.w <= 0.0 || cb.w <= 0.0) return 1.0 / 0.0;
  return floor(distance(project(first), project(second)) / mu) + 1.0;
}

// Eq. 3's levels of the four outer edges (u = x_i, v = y_j, u = x_i+1, v = y_j+1) of the KSQuad
// whose table row starts at `row`: per edge, or (vk-eq3=literal) all from the diagonal pair.
float[4] wanted_levels(int row) {
  const int c00 = patches[row + 12], c10 = patches[row + 13], c01 = patches[row + 14],
            c11 = patches[row + 15];
  const float mu = mode.mu * threshold_scale(patches[row] * SURFACE_INTS);
  if (mode.eq3_literal != 0) {
    const float tau = wanted_level(c00, c11, mu);
    return float[4](tau, tau, tau, tau);
  }
  return float[4](wanted_level(c00, c01, mu), wanted_level(c00, c10, mu),
                  wanted_level(c10, c11, mu), wanted_level(c01, c11, mu));
}

// The index of the vertex where cut k of `cuts` cuts an edge of `level` segments, as a fraction
// of the edge; cuts past the last are the edge's end.
float cut_fraction(int k, int cuts, float level) {
  return k >= cuts ? 1.0 : floor(float(k) * level / float(cuts)) / level;
}

// Segments of an edge of `level` in piece k of n (pieces past the edge's own cuts: 0).
float segments(int k, int n, int cuts, float level) {
  if (k >= cuts) return 0.0;
  return floor(float(k + 1) * level / float(cuts)) - floor(float(k) * level / float(cuts));
}

// Corner (k, l) of the pieces: on the KSQuad's outline exactly the cut of that edge; inside, the
// crossing of the line from cut k of edge 1 (v = 0) to cut k of edge 3 (v = 1) with the line
// from cut l of edge 0 (u = 0) to cut l of edge 2 (u = 1). Every piece meeting there computes it
// from the same integers, so they agree to the bit.
vec2 corner_of(int k, int l, int n_u, int n_v, int cuts[4], float level[4]) {
  const float a = cut_fraction(k, cuts[1], level[1]), c = cut_fraction(k, cuts[3], level[3]);
  const float d = cut_fraction(l, cuts[0], level[0]), e = cut_fraction(l, cuts[2], level[2]);
  if (l == 0) return vec2(k == n_u ? 1.0 : a, 0.0);
  if (l == n_v) return vec2(k == n_u ? 1.0 : c, 1.0);
  if (k == 0) return vec2(0.0, d);
  if (k == n_u) return vec2(1.0, e);
  const float fu = (a + d * (c - a)) / (1.0 - (e - d) * (c - a));
  return vec2(fu, d + fu * (e - d));
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
  } else if (mode.nonuniform != 0) {
    // Nonuniform (003 §4's third mapping): the "fewer KSDice" level of the control stage is eq. 3
    // per edge as above with mode.mu = vk-mu x 2^kNonuniformDepth (the host scales it), so the
    // geometry stage's deepest subdivision of a KSDie gives back vk-mu pixels. A KSDie is a
    // rectangle (003 §3.1: one δx, one δy), so the KSQuad's lattice is regular: each direction takes
    // the larger of its two edges' levels, capped at vk-max-level (the host counts what was cut).
    const float wanted[4] = wanted_levels(row);
    const float cap = float(mode.max_level);
    const float level_u = min(max(wanted[1], wanted[3]), cap);
    const float level_v = min(max(wanted[0], wanted[2]), cap);
    outer = float[4](level_v, level_u, level_v, level_u);
    gl_TessLevelInner[0] = level_u;
    gl_TessLevelInner[1] = level_v;
    for (int e = 0; e < 4; ++e) {
      levels[8 * PATCH + e] = outer[e];
      levels[8 * PATCH + 4 + e] = wanted[e];
    }
  } else {
    const float wanted[4] = wanted_levels(row);
    // A KSQuad's edge past the cap is cut, not capped (003 §4 leaves levels past the tessellator's
    // 64 open): the KSQuad is drawn as mode.pieces^2 patches (row + 11: this one's index), of
    // which the first n_u x n_v are used, n_u = ceil(max(L1, L3) / cap) (n_v from L0, L2); each
    // outer edge e is cut into ceil(L_e / cap) pieces on its own -- so the KSQuad across it, which
    // computes the same L_e, cuts it at the same vertices -- and pieces past that get a zero-length
    // stretch of it at its end. Levels past pieces x cap are capped (counted by the host).
    const float cap = float(mode.max_level);
    float level[4];
    int cuts[4];
    for (int e = 0; e < 4; ++e) {
      level[e] = min(wanted[e], cap * float(mode.pieces));
      cuts[e] = int(ceil(level[e] / cap));
      levels[8 * PATCH + 4 + e] = wanted[e];
    }
    const int n_u = max(cuts[1], cuts[3]), n_v = max(cuts[0], cuts[2]);
    const int piece = patches[row + 11], pu = piece % mode.pieces, pv = piece / mode.pieces;
    if (pu >= n_u || pv >= n_v) {
      outer = float[4](0.0, 0.0, 0.0, 0.0);  // not needed: discarded
      gl_TessLevelInner[0] = 0.0;
      gl_TessLevelInner[1] = 0.0;
    } else {
      // Piece corners in the KSQuad's (fu, fv) (corner_of); outer levels: segments of the
      // KSQuad's edge in this piece (at least 1: a zero-length stretch is one degenerate segment)
      // or, inside the KSQuad, the larger of the two opposite KSQuad edges' counts.
      piece_corners[0] = corner_of(pu, pv, n_u, n_v, cuts, level);
      piece_corners[1] = corner_of(pu + 1, pv, n_u, n_v, cuts, level);
      piece_corners[2] = corner_of(pu, pv + 1, n_u, n_v, cuts, level);
      piece_corners[3] = corner_of(pu + 1, pv + 1, n_u, n_v, cuts, level);
      const float along_u = max(segments(pu, n_u, cuts[1], level[1]),
                                segments(pu, n_u, cuts[3], level[3]));
      const float along_v = max(segments(pv, n_v, cuts[0], level[0]),
                                segments(pv, n_v, cuts[2], level[2]));
      outer[0] = pu == 0 ? segments(pv, n_v, cuts[0], level[0]) : along_v;
      outer[2] = pu == n_u - 1 ? segments(pv, n_v, cuts[2], level[2]) : along_v;
      outer[1] = pv == 0 ? segments(pu, n_u, cuts[1], level[1]) : along_u;
      outer[3] = pv == n_v - 1 ? segments(pu, n_u, cuts[3], level[3]) : along_u;
      for (int e = 0; e < 4; ++e) outer[e] = max(outer[e], 1.0);
      gl_TessLevelInner[0] = max(max(outer[1], outer[3]), 2.0);
      gl_TessLevelInner[1] = max(max(outer[0], outer[2]), 2.0);
    }
    for (int e = 0; e < 4; ++e) levels[8 * PATCH + e] = outer[e];
  }
  patch_row = PATCH;
  for (int e = 0; e < 4; ++e) gl_TessLevelOuter[e] = outer[e];
}
