#version 330 core
// 001 "T-splines GPU evaluation", steps 2-3, one piece of the split program: for this sample's
// region, its active control points number first .. first + POINTS_PER_PASS - 1 each add
// B_k(u, v) w_k P_k (eq. 4-5, homogeneous) to the running sums; B_k = N[u_k](u) N[v_k](v), each
// factor the B-spline on the point's own local knot vector (degree + 2 knots). With NORMALS the
// partial derivatives' sums ride along in two more targets (the quotient rule needs them). The
// sums ping-pong between two sets of targets, as 001's NURBS passes do between tex1 and tex2.
//
// Defines: DEGREE_U, DEGREE_V (odd), LB_MAX_DEGREE (the larger), POINTS_PER_PASS, NORMALS,
// LINEAR_WIDTH (region_tables.h); then local_basis.h. CPU counterpart: detail::combine_tspline
// (reference/tspline.h): the same products, summed in the same region order, in float.

uniform sampler2D previous_sum;  // per sample: sum of B_k (w x, w y, w z, w)
#if NORMALS
uniform sampler2D previous_su;  // sum of dB_k/du (w x, w y, w z, w)
uniform sampler2D previous_sv;
#endif
uniform sampler2D points;     // linear: homogeneous control points
uniform sampler2D knots_u;    // linear: point k's local u knots at k * (DEGREE_U + 2)
uniform sampler2D knots_v;
uniform isampler2D offsets;   // linear: CSR offsets per region
uniform isampler2D entries;   // linear: (point, span u, span v, 0) per entry
uniform sampler2D parameters; // per sample: (u, v)
uniform isampler2D regions;   // per sample: region
uniform int first;            // index, in the region's list, of this pass's first point

layout(location = 0) out vec4 sum;
#if NORMALS
layout(location = 1) out vec4 sum_u;
layout(location = 2) out vec4 sum_v;
#endif

ivec2 linear(int i) {
  return ivec2(i % LINEAR_WIDTH, i / LINEAR_WIDTH);
}

// (N(t), N'(t)) of the point's local B-spline: lb_local_basis (local_basis.h, prepended after
// these defines by gl-tspline) on its knots fetched from the table.
vec2 local_basis(sampler2D table, int point, int degree, int span, float t) {
  float k[LB_MAX_DEGREE + 2];
  for (int i = 0; i < degree + 2; ++i)
    k[i] = texelFetch(table, linear(point * (degree + 2) + i), 0).r;
  float value, derivative;
  lb_local_basis(degree, k, span, t, value, derivative);
  return vec2(value, derivative);
}

void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  vec4 s = texelFetch(previous_sum, at, 0);
#if NORMALS
  vec4 s_u = texelFetch(previous_su, at, 0);
  vec4 s_v = texelFetch(previous_sv, at, 0);
#endif
  vec2 uv = texelFetch(parameters, at, 0).xy;
  int region = texelFetch(regions, at, 0).r;
  int begin = texelFetch(offsets, linear(region), 0).r;
  int end = texelFetch(offsets, linear(region + 1), 0).r;
  for (int i = 0; i < POINTS_PER_PASS; ++i) {
    int e = begin + first + i;
    if (e >= end) break;  // regions have different counts: the rest of this pass is masked
    ivec4 entry = texelFetch(entries, linear(e), 0);
    vec2 nu = local_basis(knots_u, entry.x, DEGREE_U, entry.y, uv.x);
    vec2 nv = local_basis(knots_v, entry.x, DEGREE_V, entry.z, uv.y);
    vec4 p = texelFetch(points, linear(entry.x), 0);
    s += (nu.x * nv.x) * p;
#if NORMALS
    s_u += (nu.y * nv.x) * p;
    s_v += (nu.x * nv.y) * p;
#endif
  }
  sum = s;
#if NORMALS
  sum_u = s_u;
  sum_v = s_v;
#endif
}
