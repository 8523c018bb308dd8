// Evaluating a KSQuad, shared by the evaluation stage (ksquad.tese), the geometry stage of the
// GS mapping (ksquad.geom) and the corner pass (ksquad_corners.comp). The includer defines
// DEGREE_U(s) and DEGREE_V(s) and includes ksquad_tables.glsl and ../stair_basis/stair_basis.h first.

// share_parameter (ksquad_tables.glsl) on the span [x_i, x_i+1] of the stair constants c
// (SB_KNOT(c, p - 1) = x_i, SB_KNOT(c, p) = x_i+1: StairConstants::knots).
float span_parameter(int c, int p, float lo, float hi, float t) {
  return share_parameter(SB_KNOT(c, p - 1), SB_KNOT(c, p), lo, hi, t);
}

// S(u, v): the stair basis of the KSQuad's spans and A4.3 on its (p+1)(q+1) homogeneous control
// points (reference/nurbs_math.h surface_point_from_basis): rows in v first, then u.
vec3 ksquad_point(int s, int span_u, int span_v, int cu, int cv, float u, float v) {
  const int pu = DEGREE_U(s), pv = DEGREE_V(s), count_v = surfaces[s + 3];
  float bu[SB_MAX_ORDER], bv[SB_MAX_ORDER];
  stair_basis(cu, pu, u, bu, pu);
  stair_basis(cv, pv, v, bv, pv);
  vec4 sum = vec4(0.0);
  const int first = surfaces[s + 4] + (span_u - pu) * count_v + (span_v - pv);
  for (int i = 0; i <= pu; ++i) {
    vec4 row_sum = vec4(0.0);
    for (int j = 0; j <= pv; ++j) row_sum += bv[j] * points[first + i * count_v + j];
    sum += bu[i] * row_sum;
  }
  return sum.xyz / sum.w;
}

bool normalize_if_resolved(vec3 n, vec3 a, vec3 b, out vec3 unit) {
  // reference/nurbs_math.h detail::normalize_if_resolved with float's epsilon
  const float scale = length(a) + length(b);
  const float len = length(n);
  if (!(len > 1024.0 * 1.1920929e-7 * scale * scale) || isinf(len) || isnan(len)) return false;
  unit = n / len;
  return true;
}

// Unit normal from the derivatives of the same stair basis (stair_derivative): Su x Sv, or where
// a tangent vanishes the limit along the surface (reference/nurbs_math.h surface_normal's first
// two stages, line by line; its third, a nudged neighbour sample, may leave the KSQuad and is not
// done here: the zero vector is written instead). `span_u`, `cu` (and v) are the span whose
// basis is used: at a span's end knot the caller passes the next span, as A2.1 assigns the knot
// to it -- on a crease the two one-sided normals differ, and the reference takes that one.
void write_normal(int slot, int s, int span_u, int span_v, int cu, int cv, float u, float v) {
  const int pu = DEGREE_U(s), pv = DEGREE_V(s), count_v = surfaces[s + 3];
  float bu[SB_MAX_ORDER], bv[SB_MAX_ORDER], du[SB_MAX_ORDER], dv[SB_MAX_ORDER];
  stair_basis(cu, pu, u, bu, pu);
  stair_basis(cv, pv, v, bv, pv);
  stair_derivative(cu, pu, u, du);
  stair_derivative(cv, pv, v, dv);
  const int first = surfaces[s + 4] + (span_u - pu) * count_v + (span_v - pv);
  vec4 a = vec4(0.0), au = vec4(0.0), av = vec4(0.0), auv = vec4(0.0);
  for (int i = 0; i <= pu; ++i) {
    vec4 row = vec4(0.0), row_v = vec4(0.0);
    for (int j = 0; j <= pv; ++j) {
      const vec4 p = points[first + i * count_v + j];
      row += bv[j] * p;
      row_v += dv[j] * p;
    }
    a += bu[i] * row;
    au += du[i] * row;
    av += bu[i] * row_v;
    auv += du[i] * row_v;
  }
  // The quotient rule for S = A / w (A3.6 / A4.4 to first order in each direction).
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
  normals[3 * slot] = n.x;
  normals[3 * slot + 1] = n.y;
  normals[3 * slot + 2] = n.z;
}
