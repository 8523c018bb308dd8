// The storage buffers of vk-ksquad (003 Fig 8's two-level indirection): the Info-KSQuad table
// (one row per patch) points into the surface table, which points into the surface data. The
// record layouts are written by strategies/vk_ksquad/vk_ksquad.cpp (kSurfaceInts, kPatchInts).
layout(std430, set = 0, binding = 0) readonly buffer Surfaces { int surfaces[]; };
layout(std430, set = 0, binding = 1) readonly buffer Patches { int patches[]; };
layout(std430, set = 0, binding = 2) readonly buffer Constants { float consts[]; };
layout(std430, set = 0, binding = 3) readonly buffer Points { vec4 points[]; };
layout(std430, set = 0, binding = 4) readonly buffer Params { float params[]; };
layout(std430, set = 0, binding = 5) writeonly buffer Positions { float positions[]; };
// Adaptive mode: the KSQuad corners S(x_k, y_l) (xyz, w unused) -- written by ksquad_corners.comp
// (vk-corners=device) or by the host (vk-corners=host) -- and the levels each patch chose (4
// outer as set, then 4 as wanted before the cap).
#ifndef KSQUAD_CORNERS_ACCESS
#define KSQUAD_CORNERS_ACCESS readonly
#endif
layout(std430, set = 0, binding = 6) KSQUAD_CORNERS_ACCESS buffer Corners { vec4 corners[]; };
layout(std430, set = 0, binding = 7) writeonly buffer Levels { float levels[]; };
// With normals: one unit normal per sample (uniform) or per capture slot (adaptive).
layout(std430, set = 0, binding = 8) writeonly buffer Normals { float normals[]; };
// Uniform span grid: the (u, v) the tessellator's coordinate gave each sample, in the order of
// `positions` (the tessellator chooses the samples; vk_ksquad.cpp returns them).
layout(std430, set = 0, binding = 12) writeonly buffer SampleParams { float sample_params[]; };
// Adaptive, vk-corners=device: per corner, the surface's row, the span pair A2.1 assigns the
// corner's knots to and their constants, and whether u (v) is that span's end knot (the domain's
// end); CORNER_INTS ints each.
layout(std430, set = 0, binding = 13) readonly buffer CornerJobs { int corner_jobs[]; };
#define CORNER_INTS 8

layout(push_constant) uniform Mode {
  mat4 view_projection;  // adaptive: world -> clip (column-major)
  vec2 viewport;         // adaptive: pixels
  float mu;              // adaptive: largest projected KSDie edge, pixels (003 eq. 3)
  int adaptive;          // 0: uniform (levels from the table), 1: adaptive
  int max_level;         // adaptive: the level cap (<= maxTessellationGenerationLevel)
  int region;            // adaptive: capture slots per patch
  int normals;           // 1 when normals are requested
  int patch_base;        // row of this draw's first patch (one draw per degree pair)
  int span_grid;         // uniform: 1 when the parameters come from gl_TessCoord (span grid)
  int pieces;            // adaptive: patches per KSQuad and direction (vk-pieces)
} mode;
// The patch's row in the Info-KSQuad table.
#define PATCH (mode.patch_base + gl_PrimitiveID)

// surfaces: degree_u, degree_v, count_u, count_v, first point, first u parameter,
//           first v parameter, v parameters (nv), first output sample, 3 x pad,
//           the domain's ends u0, u1, v0, v1 as float bits
#define SURFACE_INTS 16
// patches: surface, span_u, span_v, u constants, v constants, u_begin, u_count, v_begin, v_count,
//          level_u, level_v, adaptive: the piece (ksquad.tesc), corners (u_lo,v_lo), (u_hi,v_lo), (u_lo,v_hi), (u_hi,v_hi),
//          the next non-empty span in u and v (the span itself at the domain's end) and their
//          constants (normals at the end knot), then the patch's share [lo, hi] of its u span and
//          of its v span as fractions (float bits; 0, 1 unless a run was cut into pieces)
#define PATCH_INTS 24
// adaptive capture: per slot u, v, x, y, z
#define SLOT_FLOATS 5

float surface_knot_u(int s, int end) { return intBitsToFloat(surfaces[s + 12 + end]); }
float surface_knot_v(int s, int end) { return intBitsToFloat(surfaces[s + 14 + end]); }

// Uniform mapping, shared with vk-bezier's evaluation stage (bezier.tese):
// The index of a tessellator vertex in its patch's run of samples [begin, begin + count), the
// run's segments being the patch's level. round: the tessellator's k / level is within a float
// ulp of the lattice point; an inner level raised from 1 to 2 by the tessellator lands on a vertex
// already there.
int lattice_index(float t, int level, int begin, int count) {
  return begin + min(int(round(t * float(level))), count - 1);
}

// The parameter the tessellator's coordinate t gives in a patch's share [lo, hi] of its knot span
// [x0, x1]. Both blends are exact at t = 0 and 1 (and lo, hi are the same floats on both sides of
// a piece boundary), so the patches meeting on a knot line or a cut evaluate the same parameter
// there.
float share_parameter(float x0, float x1, float lo, float hi, float t) {
  const float f = (1.0 - t) * lo + t * hi;
  return (1.0 - f) * x0 + f * x1;
}
