// The blending-function factor of one T-spline control point (001 eq. 5): the B-spline of
// `degree` on the point's own local knot vector k[0 .. degree + 1], value and first derivative,
// on the polynomial piece of span `span` (k[span] <= t < k[span + 1] inside the piece; beyond it,
// the piece's extension). Written ONCE in the common subset of C++ and GLSL, as
// strategies/stair_basis/stair_basis.h is: gl-tspline hands it to accumulate.frag after the
// shader's defines, and local_basis_cpp.h compiles it as C++ (float, long double) for the test
// that holds it to the reference's local_basis (Piegl & Tiller A2.2/A2.3 on padded knots). No
// include guard in C++: local_basis_cpp.h includes it once per scalar type.
//
// Cox-de Boor (001 eq. 2) from N_{span,0} = 1 up: at order r the table holds degree + 1 - r
// functions, updated in place (n[i] from n[i] and n[i + 1] of the previous order). 0/0 := 0 for
// repeated knots. The derivative is Piegl & Tiller eq. 2.9 from the order degree - 1 values.

#if defined(__cplusplus)
#include "../kernel_language/kernel_language.h"
#endif
#if defined(KL_CPP)
// The includer defines LB_REAL (float or long double).
#define LB_KNOTS_IN(name) const LB_REAL* name
#ifndef LB_MAX_DEGREE
#define LB_MAX_DEGREE 15  // reference/validation.h kMaxDegree
#endif
#else
// GLSL: the program's defines give LB_MAX_DEGREE (the larger of its two degrees), which sizes
// the arrays.
#define LB_REAL float
#define LB_KNOTS_IN(name) float name[LB_MAX_DEGREE + 2]
#endif

KL_FN LB_REAL lb_ratio(LB_REAL a, LB_REAL b) {
  return b == KL_CAST(LB_REAL, 0) ? KL_CAST(LB_REAL, 0) : a / b;
}

KL_FN void lb_local_basis(int degree, LB_KNOTS_IN(k), int span, LB_REAL t, KL_OUT(LB_REAL, value),
                          KL_OUT(LB_REAL, derivative)) {
  LB_REAL n[LB_MAX_DEGREE + 1];
  for (int i = 0; i <= degree; ++i) n[i] = i == span ? KL_CAST(LB_REAL, 1) : KL_CAST(LB_REAL, 0);
  derivative = KL_CAST(LB_REAL, 0);
  for (int r = 1; r <= degree; ++r) {
    if (r == degree)
      derivative = KL_CAST(LB_REAL, degree) *
                   (lb_ratio(n[0], k[degree] - k[0]) - lb_ratio(n[1], k[degree + 1] - k[1]));
    for (int i = 0; i <= degree - r; ++i)
      n[i] = lb_ratio((t - k[i]) * n[i], k[i + r] - k[i]) +
             lb_ratio((k[i + r + 1] - t) * n[i + 1], k[i + r + 1] - k[i + 1]);
  }
  value = n[0];
}
