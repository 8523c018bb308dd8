#version 450
#extension GL_GOOGLE_include_directive : require
// vk-bezier's evaluation stage: RPNS's baseline (003 §2) on the GPU. Each tessellation patch is
// one rational Bézier patch of the CPU's decomposition (A5.7), or a piece of one where a run of
// samples passes maxTessellationGenerationLevel; the control stage is vk-ksquad's (ksquad.tesc,
// uniform mode: the levels are the patch's run lengths), so both strategies tessellate the same
// lattices and differ only in what a vertex evaluates. The patch row has ksquad_tables.glsl's
// layout with the fields vk_bezier.cpp writes: surface, span_u, span_v, the patch's first Bézier
// point, 0, the u and v runs, the levels, 0, the span's knots x_i, x_i+1, y_j, y_j+1 (float bits),
// 4 x 0, the patch's share of its spans (float bits).
//  * grid: gl_TessCoord picks the lattice vertex (a, b) of the patch's runs and the parameter is
//    the requested one (as vk-ksquad's uniform grid);
//  * span grid: the tessellator chooses it, share_parameter() of gl_TessCoord, and it is written
//    with the position.
// The parameter is then mapped to the Bézier patch's [0, 1] and the patch evaluated with the
// Bernstein basis in homogeneous coordinates (003 Eq. 2), then divided.
layout(quads, equal_spacing, ccw) in;
layout(constant_id = 0) const int kRaster = 0;  // always 0: vk-bezier only captures
// One pipeline per degree pair, as vk-ksquad: constant loop bounds (0: read the surface table).
layout(constant_id = 1) const int kDegreeU = 0;
layout(constant_id = 2) const int kDegreeV = 0;
#include "../vk_ksquad/ksquad_tables.glsl"
layout(location = 4) patch in int patch_row;  // from ksquad.tesc

#define BEZIER_MAX_ORDER 16  // degree 15 (Capabilities::max_degree)

// The Piegl & Tiller A1.3 AllBernstein triangle: B_{k,n}(t), k = 0..n, convex combinations of
// non-negative numbers (the stability of de Casteljau, whose scheme it runs on the basis), in
// O(n^2) per parameter against de Casteljau's O(p^2 q) points per sample. As cpu-bezier does.
void all_bernstein(int n, float t, out float b[BEZIER_MAX_ORDER]) {
  b[0] = 1.0;
  const float t1 = 1.0 - t;
  for (int j = 1; j <= n; ++j) {
    float saved = 0.0;
    for (int k = 0; k < j; ++k) {
      const float temp = b[k];
      b[k] = saved + t1 * temp;
      saved = t * temp;
    }
    b[j] = saved;
  }
}

void main() {
  const int row = patch_row * PATCH_INTS;
  const int s = patches[row] * SURFACE_INTS;
  const int p = kDegreeU > 0 ? kDegreeU : surfaces[s];
  const int q = kDegreeV > 0 ? kDegreeV : surfaces[s + 1];
  const int a = lattice_index(gl_TessCoord.x, patches[row + 9], patches[row + 5], patches[row + 6]);
  const int b = lattice_index(gl_TessCoord.y, patches[row + 10], patches[row + 7], patches[row + 8]);
  const float x0 = intBitsToFloat(patches[row + 12]), x1 = intBitsToFloat(patches[row + 13]);
  const float y0 = intBitsToFloat(patches[row + 14]), y1 = intBitsToFloat(patches[row + 15]);
  float u, v;
  if (mode.span_grid != 0) {
    u = share_parameter(x0, x1, intBitsToFloat(patches[row + 20]),
                        intBitsToFloat(patches[row + 21]), gl_TessCoord.x);
    v = share_parameter(y0, y1, intBitsToFloat(patches[row + 22]),
                        intBitsToFloat(patches[row + 23]), gl_TessCoord.y);
  } else {
    u = params[surfaces[s + 5] + a];
    v = params[surfaces[s + 6] + b];
  }
  // The Bézier patch's own parameters (cpu-bezier's axis_sample): the span's knots map to 0, 1.
  float bu[BEZIER_MAX_ORDER], bv[BEZIER_MAX_ORDER];
  all_bernstein(p, (u - x0) / (x1 - x0), bu);
  all_bernstein(q, (v - y0) / (y1 - y0), bv);
  const int first = patches[row + 3];
  vec4 sum = vec4(0.0);
  for (int i = 0; i <= p; ++i) {
    vec4 row_sum = vec4(0.0);
    for (int j = 0; j <= q; ++j) row_sum += bv[j] * points[first + i * (q + 1) + j];
    sum += bu[i] * row_sum;
  }
  const vec3 position = sum.xyz / sum.w;
  const int slot = surfaces[s + 8] + a * surfaces[s + 7] + b;
  positions[3 * slot] = position.x;
  positions[3 * slot + 1] = position.y;
  positions[3 * slot + 2] = position.z;
  if (mode.span_grid != 0) {
    sample_params[2 * slot] = u;
    sample_params[2 * slot + 1] = v;
  }
}
