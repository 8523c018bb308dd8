// S(u, v) of a KSQuad: the stair basis of its spans (stair_basis.glsl) and A4.3 on its
// (p+1)(q+1) homogeneous control points (reference/nurbs_math.h surface_point_from_basis): rows
// in v first, then u. Shared by the evaluation stage and the corner pass (ksquad_corners.comp).
// The includer defines DEGREE_U(s) and DEGREE_V(s).
vec3 ksquad_point(int s, int span_u, int span_v, int cu, int cv, float u, float v) {
  const int pu = DEGREE_U(s), pv = DEGREE_V(s), count_v = surfaces[s + 3];
  float bu[MAX_ORDER], bv[MAX_ORDER];
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
