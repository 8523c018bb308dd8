#version 450
#extension GL_GOOGLE_include_directive : require
// Evaluation stage (003 §4's domain shader): evaluates the KSQuad at the tessellator's vertex
// with the stair basis and writes the position to the output buffer. The tessellator's
// coordinate picks the lattice vertex (a, b) of the patch's runs; the parameter is the requested
// one, read from the parameter buffer (the float rounding of what sample_parameters lists), so
// results are measured at exactly the requested (u, v). The slot depends only on (a, b): a
// vertex evaluated twice writes the same value to the same place.
layout(quads, equal_spacing, ccw) in;
#include "ksquad_tables.glsl"
#include "stair_basis.glsl"

void main() {
  const int row = gl_PrimitiveID * PATCH_INTS;
  const int s = patches[row] * SURFACE_INTS;
  const int span_u = patches[row + 1], span_v = patches[row + 2];
  const int cu = patches[row + 3], cv = patches[row + 4];
  const int u_begin = patches[row + 5], u_count = patches[row + 6];
  const int v_begin = patches[row + 7], v_count = patches[row + 8];
  const int level_u = patches[row + 9], level_v = patches[row + 10];
  const int pu = surfaces[s], pv = surfaces[s + 1], count_v = surfaces[s + 3];
  // round: the tessellator's k / level is within a float ulp of the lattice point; an inner
  // level raised from 1 to 2 by the tessellator lands on a vertex already there.
  const int a = u_begin + min(int(round(gl_TessCoord.x * float(level_u))), u_count - 1);
  const int b = v_begin + min(int(round(gl_TessCoord.y * float(level_v))), v_count - 1);
  const float u = params[surfaces[s + 5] + a], v = params[surfaces[s + 6] + b];
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
  const int o = 3 * (surfaces[s + 8] + a * surfaces[s + 7] + b);
  positions[o] = sum.x / sum.w;
  positions[o + 1] = sum.y / sum.w;
  positions[o + 2] = sum.z / sum.w;
}
