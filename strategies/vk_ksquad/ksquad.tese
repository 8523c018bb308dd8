#version 450
#extension GL_GOOGLE_include_directive : require
// Evaluation stage (003 §4's domain shader): evaluates the KSQuad at the tessellator's vertex
// with the stair basis and writes the result to a storage buffer.
//  * uniform: the tessellator's coordinate picks the lattice vertex (a, b) of the patch's runs;
//    the parameter is the requested one, read from the parameter buffer (the float rounding of
//    what sample_parameters lists), so results are measured at exactly the requested (u, v). The
//    slot depends only on (a, b): a vertex evaluated twice writes the same value to the same
//    place.
//  * adaptive: (u, v) = the KSQuad's span corners blended by gl_TessCoord ((1 - t) x_i + t x_i+1,
//    exact at t = 0 and 1, so both sides of a knot line see the same parameter), captured with
//    (u, v) in the patch's region of slots: one per vertex of each outer edge, then the inner
//    lattice; a slot again depends only on the vertex.
//  * raster (specialization constant 0 = 1; the render() path, 003 §4's pipeline end to end): the
//    same evaluation, the position projected to gl_Position and rasterized; nothing is stored.
layout(quads, equal_spacing, ccw) in;
layout(constant_id = 0) const int kRaster = 0;
#include "ksquad_tables.glsl"
#include "stair_basis.glsl"

int adaptive_slot() {
  const vec2 t = gl_TessCoord.xy;
  const int edge = mode.max_level + 1;
  if (t.x == 0.0) return int(round(t.y * gl_TessLevelOuter[0]));
  if (t.y == 0.0) return edge + int(round(t.x * gl_TessLevelOuter[1]));
  if (t.x == 1.0) return 2 * edge + int(round(t.y * gl_TessLevelOuter[2]));
  if (t.y == 1.0) return 3 * edge + int(round(t.x * gl_TessLevelOuter[3]));
  const int i = int(round(t.x * gl_TessLevelInner[0])), j = int(round(t.y * gl_TessLevelInner[1]));
  return 4 * edge + (i - 1) * (mode.max_level - 1) + (j - 1);
}

void main() {
  const int row = gl_PrimitiveID * PATCH_INTS;
  const int s = patches[row] * SURFACE_INTS;
  const int span_u = patches[row + 1], span_v = patches[row + 2];
  const int cu = patches[row + 3], cv = patches[row + 4];
  const int pu = surfaces[s], pv = surfaces[s + 1], count_v = surfaces[s + 3];
  float u, v;
  int a = 0, b = 0;
  if (mode.adaptive == 0) {
    const int u_begin = patches[row + 5], u_count = patches[row + 6];
    const int v_begin = patches[row + 7], v_count = patches[row + 8];
    const int level_u = patches[row + 9], level_v = patches[row + 10];
    // round: the tessellator's k / level is within a float ulp of the lattice point; an inner
    // level raised from 1 to 2 by the tessellator lands on a vertex already there.
    a = u_begin + min(int(round(gl_TessCoord.x * float(level_u))), u_count - 1);
    b = v_begin + min(int(round(gl_TessCoord.y * float(level_v))), v_count - 1);
    u = params[surfaces[s + 5] + a];
    v = params[surfaces[s + 6] + b];
  } else {
    // C_KNOT(c, p - 1) = x_i, C_KNOT(c, p) = x_{i+1} (StairConstants::knots)
    u = (1.0 - gl_TessCoord.x) * C_KNOT(cu, pu - 1) + gl_TessCoord.x * C_KNOT(cu, pu);
    v = (1.0 - gl_TessCoord.y) * C_KNOT(cv, pv - 1) + gl_TessCoord.y * C_KNOT(cv, pv);
  }
  float bu[MAX_ORDER], bv[MAX_ORDER];
  stair_basis(cu, pu, u, bu);
  stair_basis(cv, pv, v, bv);
  // A4.3 on the KSQuad's (p+1)(q+1) homogeneous control points (reference/nurbs_math.h
  // surface_point_from_basis): rows in v first, then u.
  vec4 sum = vec4(0.0);
  const int first = surfaces[s + 4] + (span_u - pu) * count_v + (span_v - pv);
  for (int i = 0; i <= pu; ++i) {
    vec4 row_sum = vec4(0.0);
    for (int j = 0; j <= pv; ++j) row_sum += bv[j] * points[first + i * count_v + j];
    sum += bu[i] * row_sum;
  }
  const vec3 position = sum.xyz / sum.w;
  if (kRaster != 0) {
    gl_Position = mode.view_projection * vec4(position, 1.0);
  } else if (mode.adaptive == 0) {
    const int o = 3 * (surfaces[s + 8] + a * surfaces[s + 7] + b);
    positions[o] = position.x;
    positions[o + 1] = position.y;
    positions[o + 2] = position.z;
  } else {
    const int o = SLOT_FLOATS * (gl_PrimitiveID * mode.region + adaptive_slot());
    positions[o] = u;
    positions[o + 1] = v;
    positions[o + 2] = position.x;
    positions[o + 3] = position.y;
    positions[o + 4] = position.z;
  }
}
