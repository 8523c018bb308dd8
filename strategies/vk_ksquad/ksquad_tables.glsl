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
  float epsilon;         // nonuniform: the linear-approximation threshold, pixels (003 eq. 4)
  float eta;             // nonuniform: the boundary-region threshold, pixels (003 eq. 5)
  int nonuniform;        // 1: the nonuniform mapping (ksquad_nonuniform.tese, .geom)
  int eq3_literal;       // adaptive: 1 = eq. 3's printed quantifiers (vk-eq3=literal, ksquad.tesc)
} mode;
// The patch's row in the Info-KSQuad table.
#define PATCH (mode.patch_base + gl_PrimitiveID)

// surfaces: degree_u, degree_v, count_u, count_v, first point, first u parameter,
//           first v parameter, v parameters (nv), first output sample, the friendless sides
//           (nonuniform), the factor of mode.mu, epsilon, eta (float bits), pad,
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
// vk-thresholds=surface: surface row s's factor of μ, ε, η (ksquad_settings.h
// surface_threshold_scales); 1 otherwise.
float threshold_scale(int s) { return intBitsToFloat(surfaces[s + 10]); }
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

bool normalize_if_resolved(vec3 n, vec3 a, vec3 b, out vec3 unit) {
  // reference/nurbs_math.h detail::normalize_if_resolved with float's epsilon
  const float scale = length(a) + length(b);
  const float len = length(n);
  if (!(len > 1024.0 * 1.1920929e-7 * scale * scale) || isinf(len) || isnan(len)) return false;
  unit = n / len;
  return true;
}

// The unit normal at (u, v) of surface row s from the homogeneous sums A = sum B P and its
// derivatives A_u, A_v, A_uv (whatever basis made them: vk-ksquad's stair basis, vk-bezier's
// Bernstein): the quotient rule for S = A / w (A3.6 / A4.4 to first order in each direction),
// Su x Sv, or where a tangent vanishes the limit along the surface (reference/nurbs_math.h
// surface_normal's first two stages, line by line; its third, a nudged neighbour sample, may leave
// the patch and is not done here: the zero vector is returned instead).
vec3 normal_from_sums(int s, vec4 a, vec4 au, vec4 av, vec4 auv, float u, float v) {
  const vec3 point = a.xyz / a.w;
  const vec3 su = (au.xyz - au.w * point) / a.w;
  const vec3 sv = (av.xyz - av.w * point) / a.w;
  const vec3 suv = (auv.xyz - auv.w * point - au.w * sv - av.w * su) / a.w;
  vec3 n = vec3(0.0);
  if (!normalize_if_resolved(cross(su, sv), su, sv, n)) {
    if (length(su) <= length(sv)) {
      // side: which end of the v domain the sample is nearer
      const float v0 = surface_knot_v(s, 0), v1 = surface_knot_v(s, 1);
      const float side = (v - v0) <= (v1 - v) ? 1.0 : -1.0;
      if (!normalize_if_resolved(side * cross(suv, sv), suv, sv, n)) n = vec3(0.0);
    } else {
      const float u0 = surface_knot_u(s, 0), u1 = surface_knot_u(s, 1);
      const float side = (u - u0) <= (u1 - u) ? 1.0 : -1.0;
      if (!normalize_if_resolved(side * cross(su, suv), su, suv, n)) n = vec3(0.0);
    }
  }
  return n;
}

void store_normal(int slot, vec3 n) {
  normals[3 * slot] = n.x;
  normals[3 * slot + 1] = n.y;
  normals[3 * slot + 2] = n.z;
}

// normal_from_sums written to normals[slot].
void write_normal_from_sums(int slot, int s, vec4 a, vec4 au, vec4 av, vec4 auv, float u, float v) {
  store_normal(slot, normal_from_sums(s, a, au, av, auv, u, v));
}
