// cl-tspline-bezier kernels (cl_tspline_bezier.cpp): a T-spline through its Bézier extraction
// (Scott et al. 2011; reference/tspline_extraction.h). REAL is float or double (build option);
// MAX_ORDER is kMaxDegree + 1.
//
// decompose_elements, one work-item per (Bernstein index kl, element): the element's homogeneous
// Bézier control point Q_kl = sum_r C_e[r][kl] (w P, w)_r -- bezier_patch() in long double, here
// in REAL and relative to an origin (below). It reruns after update_control_points(); the
// extraction operators are topology and stay.
//
// evaluate_samples, one work-item per sample: the rational Bézier patch of the sample's element
// (the element and local parameter come from the host, see cl_tspline_bezier.h) at it by
// Bernstein polynomials, and the normal from the quotient rule's first derivatives
// (reference/tspline.h combine_tspline's formulas).

// elements: 5 longs each (cl_tspline_bezier.cpp, kElementLongs): first active index, active count,
// extraction offset (reals), patch offset (reals), (p+1)(q+1). points: (x, y, z, w), Cartesian.
// A patch is its origin o (4 reals, the last unused) and then Q_kl relative to it,
// sum_r C_e[r][kl] (w (P - o), w)_r: o is the element's first active control point, so the
// evaluation's cancellations (the quotient rule's Su = (A_u - A_u.w S) / A.w) scale with the
// element's size, not with the distance to the model's origin (far-origin: 8x the normal error
// otherwise). o is taken from the current points, so an update and a fresh prepare agree bit for
// bit.
__kernel void decompose_elements(__global const long* elements, __global const int* active,
                                 __global const REAL* extraction, __global const REAL* points,
                                 __global REAL* patches) {
  const int kl = get_global_id(0);
  __global const long* e = elements + 5 * get_global_id(1);
  const int n = (int)e[4];
  if (kl >= n) return;
  const int count = (int)e[1];
  __global const int* idx = active + e[0];
  __global const REAL* c = extraction + e[2] + kl;
  // An element without active functions (outside a T-spline's blending) keeps Q = 0: its samples
  // come out NaN, like the reference's 0/0.
  REAL origin[3] = {0, 0, 0};
  if (count > 0)
    for (int d = 0; d < 3; ++d) origin[d] = points[4 * (long)idx[0] + d];
  REAL q[4] = {0, 0, 0, 0};
  for (int r = 0; r < count; ++r) {
    const REAL coefficient = c[(long)r * n];
    __global const REAL* p = points + 4 * (long)idx[r];
    const REAL w = p[3];
    for (int d = 0; d < 3; ++d) q[d] += coefficient * (w * (p[d] - origin[d]));
    q[3] += coefficient * w;
  }
  __global REAL* out = patches + e[3];
  if (kl == 0)
    for (int d = 0; d < 4; ++d) out[d] = d < 3 ? origin[d] : 0;
  for (int d = 0; d < 4; ++d) out[4 + 4 * kl + d] = q[d];
}

// The degree+1 Bernstein polynomials at t (the triangle of A1.3 in The NURBS Book: only convex
// combinations, so stable in float), and, when `derivative` is given, their t-derivatives
// degree (B^{degree-1}_{i-1} - B^{degree-1}_i) from the triangle's second-to-last row.
void bernstein(int degree, REAL t, REAL* b, REAL* derivative) {
  const REAL s = 1 - t;
  b[0] = 1;
  for (int r = 1; r <= degree; ++r) {
    if (r == degree && derivative) {
      for (int i = 0; i <= degree; ++i)
        derivative[i] = degree * ((i > 0 ? b[i - 1] : 0) - (i < degree ? b[i] : 0));
    }
    REAL saved = 0;
    for (int i = 0; i < r; ++i) {
      const REAL old = b[i];
      b[i] = saved + s * old;
      saved = t * old;
    }
    b[r] = saved;
  }
  if (degree == 0 && derivative) derivative[0] = 0;
}

// surfaces: 12 longs each (cl_tspline_bezier.cpp, kSurfaceLongs): degree_u, degree_v, tensor,
// nu, nv, parameter base, breaks base, cells_u, cells_v, patch base (reals), first sample, unused.
// params/cells: each surface's u entries then its v entries (tensor: nu then nv; explicit: one
// per sample in each), the element-local parameter in [0, 1] and the element's cell; the breaks
// give the element widths for the derivatives. Normals are written when `normals` != 0.
__kernel void evaluate_samples(__global const long* surfaces, int surface_count,
                               __global const REAL* params, __global const int* cells,
                               __global const REAL* breaks, __global const REAL* patches,
                               long total, int normals, __global REAL* positions,
                               __global REAL* normal_out) {
  const long k = get_global_id(0);
  if (k >= total) return;
  // The surface whose first sample is the last one <= k.
  int lo = 0, hi = surface_count - 1;
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (surfaces[12 * mid + 10] <= k)
      lo = mid;
    else
      hi = mid - 1;
  }
  __global const long* s = surfaces + 12 * lo;
  const int pu = (int)s[0], pv = (int)s[1];
  const long nu = s[3], nv = s[4], own = k - s[10];
  long iu, iv;
  if (s[2]) {
    iu = s[5] + own / nv;
    iv = s[5] + nu + own % nv;
  } else {
    iu = s[5] + own;
    iv = s[5] + nu + own;
  }
  const int cu = cells[iu], cv = cells[iv];
  const int cells_v = (int)s[8];
  __global const REAL* bu_breaks = breaks + s[6];
  __global const REAL* bv_breaks = bu_breaks + s[7] + 1;
  const REAL hu = bu_breaks[cu + 1] - bu_breaks[cu], hv = bv_breaks[cv + 1] - bv_breaks[cv];
  REAL bu[MAX_ORDER], bv[MAX_ORDER], du[MAX_ORDER], dv[MAX_ORDER];
  bernstein(pu, params[iu], bu, normals ? du : 0);
  bernstein(pv, params[iv], bv, normals ? dv : 0);
  __global const REAL* origin =
      patches + s[9] + 4 * (long)(cu * cells_v + cv) * ((pu + 1) * (pv + 1) + 1);
  __global const REAL* q = origin + 4;
  REAL a[4] = {0, 0, 0, 0}, au[4] = {0, 0, 0, 0}, av[4] = {0, 0, 0, 0};
  for (int i = 0; i <= pu; ++i) {
    REAL row[4] = {0, 0, 0, 0}, row_v[4] = {0, 0, 0, 0};
    for (int j = 0; j <= pv; ++j) {
      __global const REAL* qij = q + 4 * (i * (pv + 1) + j);
      for (int c = 0; c < 4; ++c) row[c] += bv[j] * qij[c];
      if (normals)
        for (int c = 0; c < 4; ++c) row_v[c] += dv[j] * qij[c];
    }
    for (int c = 0; c < 4; ++c) a[c] += bu[i] * row[c];
    if (normals)
      for (int c = 0; c < 4; ++c) {
        au[c] += du[i] * row[c];
        av[c] += bu[i] * row_v[c];
      }
  }
  REAL point[3];  // relative to the patch's origin
  for (int c = 0; c < 3; ++c) point[c] = a[c] / a[3];
  __global REAL* o = positions + 3 * k;
  for (int c = 0; c < 3; ++c) o[c] = origin[c] + point[c];
  if (!normals) return;
  // Quotient rule; the local-parameter derivatives scale by 1/h (chain rule).
  REAL su[3], sv[3];
  for (int c = 0; c < 3; ++c) {
    su[c] = (au[c] - au[3] * point[c]) / (a[3] * hu);
    sv[c] = (av[c] - av[3] * point[c]) / (a[3] * hv);
  }
  const REAL n[3] = {su[1] * sv[2] - su[2] * sv[1], su[2] * sv[0] - su[0] * sv[2],
                     su[0] * sv[1] - su[1] * sv[0]};
  // reference/nurbs_math.h normalize_if_resolved: zero where Su x Sv is rounding noise.
  const REAL scale = sqrt(su[0] * su[0] + su[1] * su[1] + su[2] * su[2]) +
                     sqrt(sv[0] * sv[0] + sv[1] * sv[1] + sv[2] * sv[2]);
  const REAL length = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const bool resolved = length > 1024 * EPSILON * scale * scale && isfinite(length);
  __global REAL* no = normal_out + 3 * k;
  for (int c = 0; c < 3; ++c) no[c] = resolved ? n[c] / length : 0;
}
