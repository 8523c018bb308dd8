// cl-stair kernel (003 §3.2): one work-group per KSQuad. The group caches the KSQuad's
// (p+1)(q+1) homogeneous control points and both directions' per-span constants (stair_constants)
// in local memory, then its work-items evaluate the KSQuad's samples with the stair basis.
// Mirrors strategies/cl_stair/stair_basis.h line by line; REAL is float or double (build option).
#ifdef STAIR_FP64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
#endif

#define MAX_DEG 9  // kStairMaxDegree
#define MAX_ORDER (MAX_DEG + 1)

// StairConstants<T>: the constants of one direction of one KSQuad.
typedef struct {
  REAL knots[2 * MAX_DEG];
  REAL r[MAX_DEG][MAX_DEG];
  REAL column[MAX_ORDER];
  REAL diagonal[MAX_ORDER];
} StairConstants;

// stair_basis.h: stair_constants
void stair_constants(int span, int degree, __global const REAL* knots, __local StairConstants* c) {
  const int p = degree;
  for (int t = 0; t < 2 * p; ++t) c->knots[t] = knots[span - p + 1 + t];
  for (int s = 0; s < p; ++s)
    for (int t = 0; t < p; ++t) c->r[s][t] = (REAL)1 / (c->knots[p + t] - c->knots[p - 1 - s]);
  c->column[0] = (REAL)1;
  c->diagonal[0] = (REAL)1;
  for (int l = 1; l <= p; ++l) {
    c->column[l] = c->column[l - 1] * c->r[0][l - 1];
    c->diagonal[l] = c->diagonal[l - 1] * c->r[l - 1][0];
  }
}

// stair_basis.h: stair_basis
void stair_basis(__local const StairConstants* c, int degree, REAL u, REAL* basis) {
  const int p = degree;
  REAL dl[MAX_ORDER], dr[MAX_ORDER];
  for (int s = 0; s < p; ++s) {
    dl[s] = u - c->knots[p - 1 - s];
    dr[s] = c->knots[p + s] - u;
  }
  REAL col[MAX_ORDER], diag[MAX_ORDER];
  col[0] = (REAL)1;
  diag[0] = (REAL)1;
  REAL pow_l = (REAL)1, pow_r = (REAL)1;
  for (int m = 1; m <= p; ++m) {
    pow_l *= dl[0];
    pow_r *= dr[0];
    col[m] = pow_l * c->column[m];
    diag[m] = pow_r * c->diagonal[m];
  }
  basis[p] = col[p];
  basis[0] = diag[p];
  for (int k = 1; k < p; ++k) {
    const int w = p - k;
    REAL t[MAX_DEG];
    REAL sum = (REAL)0;
    for (int r = 0; r < k; ++r) {
      for (int l = 0; l < w; ++l) {
        const REAL from_above =
            r > 0 ? t[l] * (dr[w - l] * c->r[k - r][w - l]) : (REAL)(l == 0 ? 1 : 0);
        const REAL from_left = l == 0 ? (REAL)0 : t[l - 1] * (dl[k - r] * c->r[k - r][w - l]);
        t[l] = from_above + from_left;
      }
      sum += t[w - 1] * (dl[k - r] * c->r[k - r][0]) * diag[k - r];
    }
    for (int l = 0; l < w; ++l) sum += t[l] * (dr[w - l] * c->r[0][w - l]) * col[w - l];
    basis[p - k] = sum;
  }
}

// surfaces: 12 ints each (see cl_stair.cpp, SurfaceRecord); ksquads: 8 ints each (KSQuadRecord).
__kernel void evaluate_ksquads(__global const int* surfaces, __global const int* ksquads,
                               __global const REAL* knots, __global const REAL* points,
                               __global const REAL* params, __global REAL* out) {
  __local StairConstants cu, cv;
  __local REAL cp[MAX_ORDER * MAX_ORDER * 4];
  __global const int* q = ksquads + 8 * get_group_id(0);
  __global const int* s = surfaces + 12 * q[0];
  const int pu = s[0], pv = s[1], count_v = s[3];
  const int span_u = q[1], span_v = q[2];
  const int lid = get_local_id(0), lsize = get_local_size(0);
  // The KSQuad's (p+1)(q+1) homogeneous control points, cooperatively.
  const int ncp = (pu + 1) * (pv + 1);
  for (int k = lid; k < ncp; k += lsize) {
    const int a = k / (pv + 1), b = k % (pv + 1);
    __global const REAL* src =
        points + s[6] + 4 * ((span_u - pu + a) * count_v + (span_v - pv + b));
    for (int c = 0; c < 4; ++c) cp[4 * k + c] = src[c];
  }
  if (lid == 0) stair_constants(span_u, pu, knots + s[4], &cu);
  if (lid == (lsize > 1 ? 1 : 0)) stair_constants(span_v, pv, knots + s[5], &cv);
  barrier(CLK_LOCAL_MEM_FENCE);

  const int u_begin = q[3], u_count = q[4], v_begin = q[5], v_count = q[6];
  const int nv = s[9];
  for (int k = lid; k < u_count * v_count; k += lsize) {
    const int a = u_begin + k / v_count, b = v_begin + k % v_count;
    REAL bu[MAX_ORDER], bv[MAX_ORDER];
    stair_basis(&cu, pu, params[s[7] + a], bu);
    stair_basis(&cv, pv, params[s[8] + b], bv);
    // A4.3 on the cached net (reference/nurbs_math.h surface_point_from_basis)
    REAL sum[4] = {0, 0, 0, 0};
    for (int i = 0; i <= pu; ++i) {
      REAL row[4] = {0, 0, 0, 0};
      for (int j = 0; j <= pv; ++j)
        for (int c = 0; c < 4; ++c) row[c] += bv[j] * cp[4 * (i * (pv + 1) + j) + c];
      for (int c = 0; c < 4; ++c) sum[c] += bu[i] * row[c];
    }
    __global REAL* o = out + 3 * ((long)s[10] + (long)a * nv + b);
    o[0] = sum[0] / sum[3];
    o[1] = sum[1] / sum[3];
    o[2] = sum[2] / sum[3];
  }
}

// Test kernel: the stair basis of one direction at n parameters of one span (tests only).
__kernel void stair_basis_test(int span, int degree, __global const REAL* knots,
                               __global const REAL* u, int n, __global REAL* basis) {
  __local StairConstants c;
  if (get_local_id(0) == 0) stair_constants(span, degree, knots, &c);
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int k = get_local_id(0); k < n; k += get_local_size(0)) {
    REAL b[MAX_ORDER];
    stair_basis(&c, degree, u[k], b);
    for (int j = 0; j <= degree; ++j) basis[k * (degree + 1) + j] = b[j];
  }
}
