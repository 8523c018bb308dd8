// vk-compute's basis pass, written ONCE in the common subset of C++ and GLSL (the single-source
// style of strategies/stair_basis/stair_basis.h): compiled as C++ (function templates on the
// scalar; the strategy's tile layout and the tests use it) and as GLSL by basis.glsl in float and
// double (the basis pass of the strategy, and the test that runs it on lavapipe against the C++
// build, tests/strategies/vk_compute/basis_test.cpp).
//
// The algorithms are the reference's (reference/nurbs_math.h): find_span is A2.1 with the same
// end conventions (a bisection instead of std::upper_bound, the same answer: the last knot <= u
// in [degree, count]); the basis functions are A2.2. First derivatives come from the degree p-1
// functions A2.2 leaves one step before the end, by Piegl & Tiller eq. (2.7):
//   N'_{i,p} = p (N_{i,p-1} / (x_{i+p} - x_i) - N_{i+1,p-1} / (x_{i+p+1} - x_{i+1}))
// rather than A2.3's full table: the same values up to rounding (the reference's A2.3 is the
// oracle in the tests), one extra loop instead of a (p+1)^2 table per parameter. Every
// denominator spans the non-empty span, so no 0/0 can occur.
#if defined(__cplusplus)
#pragma once
#endif
#if defined(__cplusplus) || defined(GL_GOOGLE_include_directive)
#include "../kernel_language/kernel_language.h"
#endif
#if defined(KL_CPP)
// C++: function templates on the scalar TB_REAL.
#define TB_FN                 \
  template <typename TB_REAL> \
  KL_FN
#define TB_KNOTS const TB_REAL*
#define TB_KNOT(k, i) (k)[i]
#else
// GLSL: the includer defines TB_REAL (float or double) and declares the storage buffer
// `tb_knots` of TB_REAL; a knot vector is its offset there (a function cannot take a buffer).
#define TB_FN KL_FN
#define TB_KNOTS int
#define TB_KNOT(k, i) tb_knots[(k) + (i)]
#endif

// reference/validation.h kMaxDegree.
#define TB_MAX_DEG 15
#define TB_MAX_ORDER (TB_MAX_DEG + 1)
// The basis pass's output per parameter: TB_MAX_ORDER values, then TB_MAX_ORDER derivatives.
#define TB_STRIDE (2 * TB_MAX_ORDER)

// A2.1: s with knots[s] <= u < knots[s+1]; the end parameter (and anything past it, NaN included)
// in the last non-empty span, anything before the start in the first.
TB_FN int tb_find_span(int degree, int count, TB_KNOTS knots, TB_REAL u) {
  if (!(u < TB_KNOT(knots, count))) {
    int s = count - 1;
    while (!(TB_KNOT(knots, s) < TB_KNOT(knots, s + 1))) --s;
    return s;
  }
  if (!(u > TB_KNOT(knots, degree))) u = TB_KNOT(knots, degree);
  // knots[lo] <= u < knots[hi] throughout
  int lo = degree;
  int hi = count;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (TB_KNOT(knots, mid) <= u)
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

// basis[j] = N_{span-p+j,p}(u), j = 0..p (A2.2); with `derivatives`, ders[j] = N'_{span-p+j,p}(u)
// (eq. 2.7 on the degree p-1 functions), else ders is not written.
TB_FN void tb_basis(int span, TB_REAL u, int degree, TB_KNOTS knots,
                    KL_ARRAY_OUT(TB_REAL, basis, TB_MAX_ORDER),
                    KL_ARRAY_OUT(TB_REAL, ders, TB_MAX_ORDER), bool derivatives) {
  TB_REAL left[TB_MAX_ORDER];
  TB_REAL right[TB_MAX_ORDER];
  basis[0] = KL_CAST(TB_REAL, 1);
  for (int j = 1; j <= degree; ++j) {
    if (derivatives && j == degree) {
      // basis[r] = N_{span-p+1+r,p-1}, r = 0..p-1
      for (int r = 0; r <= degree; ++r) {
        TB_REAL d = KL_CAST(TB_REAL, 0);
        if (r >= 1)
          d += basis[r - 1] / (TB_KNOT(knots, span + r) - TB_KNOT(knots, span + r - degree));
        if (r < degree)
          d -= basis[r] / (TB_KNOT(knots, span + r + 1) - TB_KNOT(knots, span + r + 1 - degree));
        ders[r] = KL_CAST(TB_REAL, degree) * d;
      }
    }
    left[j] = u - TB_KNOT(knots, span + 1 - j);
    right[j] = TB_KNOT(knots, span + j) - u;
    TB_REAL saved = KL_CAST(TB_REAL, 0);
    for (int r = 0; r < j; ++r) {
      const TB_REAL temp = basis[r] / (right[r + 1] + left[j - r]);
      basis[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    basis[j] = saved;
  }
}
