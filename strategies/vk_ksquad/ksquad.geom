#version 450
#extension GL_GOOGLE_include_directive : require
// 003 §4's first mapping, GS-based RPNS: no tessellator; the geometry stage gets one point per
// KSQuad (ksquad.vert, gl_PrimitiveIDIn as the row of the Info-KSQuad table) and generates its
// KSDice itself on the span grid's (T+1)^2 lattice, T = the patch's level (span grid only).
//  * capture (kRaster = 0): positions, normals and the lattice parameters to storage buffers, in
//    the slots of the uniform mapping; nothing emitted.
//  * raster: T triangle strips of 2 (T + 1) vertices. The output bound is what 003 says limits
//    this mapping: max_vertices x (4 + 2 + 1 components) must fit maxGeometryTotalOutputComponents
//    (1024 on lavapipe, as D3D's 1024 scalars), so T <= 8: kGsMaxSteps in vk_ksquad.cpp, which
//    refuses larger span grids in this mode.
layout(points) in;
layout(triangle_strip, max_vertices = 144) out;  // T = 8: 8 strips x 18
layout(constant_id = 0) const int kRaster = 0;
layout(constant_id = 1) const int kDegreeU = 0;
layout(constant_id = 2) const int kDegreeV = 0;
#define DEGREE_U(s) (kDegreeU > 0 ? kDegreeU : surfaces[s])
#define DEGREE_V(s) (kDegreeV > 0 ? kDegreeV : surfaces[(s) + 1])
#include "ksquad_tables.glsl"
#undef PATCH
#define PATCH (mode.patch_base + gl_PrimitiveIDIn)
// The single-source stair basis (stair_basis, stair_derivative) on the `consts` buffer.
#include "../stair_basis/stair_basis.h"
#include "ksquad_point.glsl"
layout(location = 0) out vec2 trim_uv;
layout(location = 1) flat out int trim_surface;

void main() {
  const int row = PATCH * PATCH_INTS;
  const int s = patches[row] * SURFACE_INTS;
  const int span_u = patches[row + 1], span_v = patches[row + 2];
  const int cu = patches[row + 3], cv = patches[row + 4];
  const int pu = DEGREE_U(s), pv = DEGREE_V(s);
  const int level_u = patches[row + 9], level_v = patches[row + 10];
  const float u_lo = intBitsToFloat(patches[row + 20]), u_hi = intBitsToFloat(patches[row + 21]);
  const float v_lo = intBitsToFloat(patches[row + 22]), v_hi = intBitsToFloat(patches[row + 23]);
  if (kRaster == 0) {
    for (int a = 0; a < patches[row + 6]; ++a)
      for (int b = 0; b < patches[row + 8]; ++b) {
        // the lattice parameter a / T in float: exact at 0 and 1, as the tessellator's
        const float u = span_parameter(cu, pu, u_lo, u_hi, float(a) / float(level_u));
        const float v = span_parameter(cv, pv, v_lo, v_hi, float(b) / float(level_v));
        const vec3 position = ksquad_point(s, span_u, span_v, cu, cv, u, v);
        const int slot = surfaces[s + 8] + (patches[row + 5] + a) * surfaces[s + 7] +
                         patches[row + 7] + b;
        positions[3 * slot] = position.x;
        positions[3 * slot + 1] = position.y;
        positions[3 * slot + 2] = position.z;
        sample_params[2 * slot] = u;
        sample_params[2 * slot + 1] = v;
        if (mode.normals != 0) {
          // SB_KNOT(c, p) = x_{i+1}: the span's end knot belongs to the next span (row + 16..19)
          const bool u_end = u == SB_KNOT(cu, pu), v_end = v == SB_KNOT(cv, pv);
          write_normal(slot, s, u_end ? patches[row + 16] : span_u,
                       v_end ? patches[row + 17] : span_v, u_end ? patches[row + 18] : cu,
                       v_end ? patches[row + 19] : cv, u, v);
        }
      }
    return;
  }
  for (int b = 0; b < level_v; ++b) {
    for (int a = 0; a <= level_u; ++a)
      for (int side = 0; side < 2; ++side) {
        const float u = span_parameter(cu, pu, u_lo, u_hi, float(a) / float(level_u));
        const float v = span_parameter(cv, pv, v_lo, v_hi, float(b + side) / float(level_v));
        gl_Position = mode.view_projection * vec4(ksquad_point(s, span_u, span_v, cu, cv, u, v), 1.0);
        trim_uv = vec2(u, v);
        trim_surface = patches[row];
        EmitVertex();
      }
    EndPrimitive();
  }
}
