// De Boor's triangular scheme in homogeneous coordinates (002 §3.2, Eqs. 5-7; Piegl & Tiller
// A5.1's corner-cutting form), written ONCE in the common subset of C++ and GLSL, as
// strategies/stair_basis/stair_basis.h and strategies/gl_tspline/local_basis.h are: de_boor.h
// compiles it as C++ (float, double, long double) for the CPU composition the tests hold to
// nurbs::surface_point, and glsl-deboor hands it to de_boor.frag after the program's defines (GL
// 3.3 GLSL has no #include). The few differences are the macros below. No include guard in C++:
// de_boor.h includes it once per scalar type.
//
// The knots come as the 2p values around the span, K[t] = knots[span - p + 1 + t] for
// t = 0..2p-1 (002 §3.3.2: "the related knot vector ... transferred as uniform variables"), so the
// evaluator never searches for the span: the caller tells it.
//
// d[0..p] = the p+1 homogeneous control points P_{span-p} .. P_span on entry; returns C(u).
// Eq. (6): d_j <- (1 - alpha) d_{j-1} + alpha d_j, Eq. (7): alpha = (u - u_j) / (u_{j+k} - u_j),
// with the knot indices shifted into K. Every denominator contains the non-empty span. The update
// is written per component in both languages so that each component sees the same two products
// and one sum, in the same order.

#if defined(__cplusplus)
#include "../kernel_language/kernel_language.h"
#endif
#if defined(KL_CPP)
// The includer defines DB_REAL (float, double or long double); Vec4 is reference/nurbs_math.h's.
#define DB_VEC4 Vec4<DB_REAL>
#define DB_KNOTS_IN(name) const DB_REAL* name
#define DB_POINTS_INOUT(name) Vec4<DB_REAL>* name
#else
// GLSL: the program's defines give DEGREE, which sizes the arrays (one program per degree: see
// de_boor.frag).
#define DB_REAL float
#define DB_VEC4 vec4
#define DB_KNOTS_IN(name) float name[2 * DEGREE]
#define DB_POINTS_INOUT(name) inout vec4 name[DEGREE + 1]
#endif

KL_FN DB_VEC4 db_de_boor(int degree, DB_KNOTS_IN(K), DB_REAL u, DB_POINTS_INOUT(d)) {
  for (int r = 1; r <= degree; ++r)
    for (int j = degree; j >= r; --j) {
      DB_REAL alpha = (u - K[j - 1]) / (K[j + degree - r] - K[j - 1]);
      for (int c = 0; c < 4; ++c)
        d[j][c] = (KL_CAST(DB_REAL, 1) - alpha) * d[j - 1][c] + alpha * d[j][c];
    }
  return d[degree];
}

#undef DB_VEC4
#undef DB_KNOTS_IN
#undef DB_POINTS_INOUT
