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

// Unit normal from the derivatives of the same stair basis (stair_derivative), through
// normal_from_sums (ksquad_tables.glsl). `span_u`, `cu` (and v) are the span whose
// basis is used: at a span's end knot the caller passes the next span, as A2.1 assigns the knot
// to it -- on a crease the two one-sided normals differ, and the reference takes that one.
vec3 ksquad_normal(int s, int span_u, int span_v, int cu, int cv, float u, float v) {
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
  return normal_from_sums(s, a, au, av, auv, u, v);
}

void write_normal(int slot, int s, int span_u, int span_v, int cu, int cv, float u, float v) {
  store_normal(slot, ksquad_normal(s, span_u, span_v, cu, cv, u, v));
}
