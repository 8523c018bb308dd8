#version 450
#extension GL_GOOGLE_include_directive : require
// vk-bezier's evaluation stage: RPNS's baseline (003 §2) on the GPU. Each tessellation patch is
// one rational Bézier patch of the CPU's decomposition (A5.7), or a piece of one where a run of
// samples passes maxTessellationGenerationLevel; the control stage is vk-ksquad's (ksquad.tesc,
// uniform mode: the levels are the patch's run lengths), so both strategies tessellate the same
// lattices and differ only in what a vertex evaluates. The patch row has ksquad_tables.glsl's
// layout with the fields vk_bezier.cpp writes: surface, span_u, span_v, the patch's first Bézier
// point (relative to the patch's origin, the vec4 before it), 0, the u and v runs, the levels, 0, the span's knots x_i, x_i+1, y_j, y_j+1 (float bits),
// the offsets of the next Bézier patch in u and in v (0: none) and the end knots of their spans
// (float bits), the patch's share of its spans (float bits).
//  * grid: gl_TessCoord picks the lattice vertex (a, b) of the patch's runs and the parameter is
//    the requested one (as vk-ksquad's uniform grid);
//  * span grid: the tessellator chooses it, share_parameter() of gl_TessCoord, and it is written
//    with the position.
// The parameter is then mapped to the Bézier patch's [0, 1] and the patch evaluated with the
// Bernstein basis in homogeneous coordinates (003 Eq. 2), then divided. Normals (mode.normals):
// the Bernstein derivatives of the same triangle and vk-ksquad's write_normal_from_sums.
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
// O(n^2) per parameter against de Casteljau's O(p^2 q) points per sample. Mirrors the tested C++
// all_bernstein of strategies/cpu_bezier/cpu_bezier.cpp line by line.
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

// B_{k,n}(t) as all_bernstein (the same operations: the last level of the triangle) and their
// derivatives d/dx = scale (B_{k-1,n-1} - B_{k,n-1}) from the level before, scale = n / (x1 - x0)
// (The NURBS Book ch. 1; the chain rule through the span's length). Mirrors cpu-bezier's
// axis_sample (derivatives branch) line by line.
void bernstein_derivative(int n, float t, float scale, out float b[BEZIER_MAX_ORDER],
                          out float d[BEZIER_MAX_ORDER]) {
  float lower[BEZIER_MAX_ORDER];
  all_bernstein(n - 1, t, lower);
  const float t1 = 1.0 - t;
  float saved = 0.0;
  for (int k = 0; k < n; ++k) {
    b[k] = saved + t1 * lower[k];
    saved = t * lower[k];
  }
  b[n] = saved;
  for (int k = 0; k <= n; ++k)
    d[k] = scale * ((k > 0 ? lower[k - 1] : 0.0) - (k < n ? lower[k] : 0.0));
}

// The normal at (u, v) from Bézier patch `first` on the spans [x0, x1] x [y0, y1].
void write_normal(int slot, int s, int p, int q, int first, float x0, float x1, float y0, float y1,
                  float u, float v) {
  float bu[BEZIER_MAX_ORDER], bv[BEZIER_MAX_ORDER], du[BEZIER_MAX_ORDER], dv[BEZIER_MAX_ORDER];
  bernstein_derivative(p, (u - x0) / (x1 - x0), float(p) / (x1 - x0), bu, du);
  bernstein_derivative(q, (v - y0) / (y1 - y0), float(q) / (y1 - y0), bv, dv);
  vec4 a = vec4(0.0), au = vec4(0.0), av = vec4(0.0), auv = vec4(0.0);
  for (int i = 0; i <= p; ++i) {
    vec4 row = vec4(0.0), row_v = vec4(0.0);
    for (int j = 0; j <= q; ++j) {
      const vec4 pt = points[first + i * (q + 1) + j];
      row += bv[j] * pt;
      row_v += dv[j] * pt;
    }
    a += bu[i] * row;
    au += du[i] * row;
    av += bu[i] * row_v;
    auv += du[i] * row_v;
  }
  write_normal_from_sums(slot, s, a, au, av, auv, u, v);
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
  // A span non-empty in double but empty in float (knots closer than a float ulp: linkrods.step's
  // face 33) has one float parameter, its start: t = 0 (not 0 / 0), the patch's exact corner row.
  float bu[BEZIER_MAX_ORDER], bv[BEZIER_MAX_ORDER];
  all_bernstein(p, x1 > x0 ? (u - x0) / (x1 - x0) : 0.0, bu);
  all_bernstein(q, y1 > y0 ? (v - y0) / (y1 - y0) : 0.0, bv);
  const int first = patches[row + 3];
  vec4 sum = vec4(0.0);
  for (int i = 0; i <= p; ++i) {
    vec4 row_sum = vec4(0.0);
    for (int j = 0; j <= q; ++j) row_sum += bv[j] * points[first + i * (q + 1) + j];
    sum += bu[i] * row_sum;
  }
  // The patch's points are relative to its origin, stored before them (vk_bezier.cpp).
  const vec3 position = points[first - 1].xyz + sum.xyz / sum.w;
  const int slot = surfaces[s + 8] + a * surfaces[s + 7] + b;
  if (mode.normals != 0) {
    // At a span's end knot the next span's patch, as A2.1 assigns the knot to it (ksquad.tese):
    // on a crease the one-sided normals differ, and the reference takes that one.
    int nfirst = first;
    float nx0 = x0, nx1 = x1, ny0 = y0, ny1 = y1;
    if (u == x1 && patches[row + 16] != 0) {
      nfirst += patches[row + 16];
      nx0 = x1;
      nx1 = intBitsToFloat(patches[row + 18]);
    }
    if (v == y1 && patches[row + 17] != 0) {
      nfirst += patches[row + 17];
      ny0 = y1;
      ny1 = intBitsToFloat(patches[row + 19]);
    }
    write_normal(slot, s, p, q, nfirst, nx0, nx1, ny0, ny1, u, v);
  }
  positions[3 * slot] = position.x;
  positions[3 * slot + 1] = position.y;
  positions[3 * slot + 2] = position.z;
  if (mode.span_grid != 0) {
    sample_params[2 * slot] = u;
    sample_params[2 * slot + 1] = v;
  }
}
