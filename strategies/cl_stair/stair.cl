// cl-stair kernel (003 §3.2): one work-group per tile of a KSQuad (a record of `ksquads` is a
// KSQuad's spans and a rectangle of its samples; cl_stair.cpp tile_ksquads says why tiles). The
// group caches the KSQuad's (p+1)(q+1) homogeneous control points and both directions' per-span
// constants (stair_constants) in local memory, then its work-items evaluate the tile's samples
// with the stair basis.
// cl_stair.cpp prepends the single-source strategies/stair_basis/stair_basis.h (stair_constants,
// stair_basis; SB_REAL is float or double, a build option).

// surfaces: 12 ints each (cl_stair.cpp upload); ksquads: 8 ints each (cl_stair.cpp tile_ksquads:
// surface, u span, v span, first u sample, u count, first v sample, v count, unused).
__kernel void evaluate_ksquads(__global const int* surfaces, __global const int* ksquads,
                               __global const SB_REAL* knots, __global const SB_REAL* points,
                               __global const SB_REAL* params, __global SB_REAL* out,
                               __local SB_REAL* cp) {
  // cp: 4 (p+1)(q+1) reals for the scene's largest degrees, sized by the host (cl_stair.cpp
  // checks it against CL_DEVICE_LOCAL_MEM_SIZE): a fixed array for degree 15 would take 8 KiB
  // in double on every KSQuad whatever the scene's degrees.
  __local SB_REAL cu[SB_CONSTANT_REALS], cv[SB_CONSTANT_REALS];
  __global const int* q = ksquads + 8 * get_group_id(0);
  __global const int* s = surfaces + 12 * q[0];
  const int pu = s[0], pv = s[1], count_v = s[3];
  const int span_u = q[1], span_v = q[2];
  const int lid = get_local_id(0), lsize = get_local_size(0);
  // The KSQuad's (p+1)(q+1) homogeneous control points, cooperatively.
  const int ncp = (pu + 1) * (pv + 1);
  for (int k = lid; k < ncp; k += lsize) {
    const int a = k / (pv + 1), b = k % (pv + 1);
    __global const SB_REAL* src =
        points + s[6] + 4 * ((span_u - pu + a) * count_v + (span_v - pv + b));
    for (int c = 0; c < 4; ++c) cp[4 * k + c] = src[c];
  }
  if (lid == 0) stair_constants(span_u, pu, knots + s[4], cu);
  if (lid == (lsize > 1 ? 1 : 0)) stair_constants(span_v, pv, knots + s[5], cv);
  barrier(CLK_LOCAL_MEM_FENCE);

  const int u_begin = q[3], u_count = q[4], v_begin = q[5], v_count = q[6];
  const int nv = s[9];
  for (int k = lid; k < u_count * v_count; k += lsize) {
    const int a = u_begin + k / v_count, b = v_begin + k % v_count;
    SB_REAL bu[SB_MAX_ORDER], bv[SB_MAX_ORDER];
    stair_basis(cu, pu, params[s[7] + a], bu, pu);
    stair_basis(cv, pv, params[s[8] + b], bv, pv);
    // A4.3 on the cached net (reference/nurbs_math.h surface_point_from_basis)
    SB_REAL sum[4] = {0, 0, 0, 0};
    for (int i = 0; i <= pu; ++i) {
      SB_REAL row[4] = {0, 0, 0, 0};
      for (int j = 0; j <= pv; ++j)
        for (int c = 0; c < 4; ++c) row[c] += bv[j] * cp[4 * (i * (pv + 1) + j) + c];
      for (int c = 0; c < 4; ++c) sum[c] += bu[i] * row[c];
    }
    __global SB_REAL* o = out + 3 * ((long)s[10] + (long)a * nv + b);
    o[0] = sum[0] / sum[3];
    o[1] = sum[1] / sum[3];
    o[2] = sum[2] / sum[3];
  }
}

// Test kernel: the stair basis (derivative = 0) or its derivative (1) of one direction at n
// parameters of one span (tests only).
__kernel void stair_basis_test(int span, int degree, __global const SB_REAL* knots,
                               __global const SB_REAL* u, int n, __global SB_REAL* basis,
                               int derivative) {
  __local SB_REAL c[SB_CONSTANT_REALS];
  if (get_local_id(0) == 0) stair_constants(span, degree, knots, c);
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int k = get_local_id(0); k < n; k += get_local_size(0)) {
    SB_REAL b[SB_MAX_ORDER];
    if (derivative)
      stair_derivative(c, degree, u[k], b);
    else
      stair_basis(c, degree, u[k], b, degree);
    for (int j = 0; j <= degree; ++j) basis[k * (degree + 1) + j] = b[j];
  }
}
