// De Boor's triangular scheme in homogeneous coordinates (002 §3.2, Eqs. 5-7; Piegl & Tiller
// A5.1's corner-cutting form), written once: the CPU copy the tests check against
// nurbs::surface_point, and the one de_boor.frag mirrors line by line.
//
// The knots come as the 2p values around the span, K[t] = knots[span - p + 1 + t] for
// t = 0..2p-1 (002 §3.3.2: "the related knot vector ... transferred as uniform variables"), so the
// evaluator never searches for the span: the caller tells it.
#pragma once

#include "reference/nurbs_math.h"

namespace nurbs::glsl_deboor {

// The 2p knots de Boor reads for span `span` of a degree-p knot vector.
template <typename T>
void span_knots(int degree, int span, const T* knots, T* K) {
  for (int t = 0; t < 2 * degree; ++t) K[t] = knots[span - degree + 1 + t];
}

// d[0..p] = the p+1 homogeneous control points P_{span-p} .. P_span on entry; returns C(u).
// Eq. (6): d_j <- (1 - alpha) d_{j-1} + alpha d_j, Eq. (7): alpha = (u - u_j) / (u_{j+k} - u_j),
// with the knot indices shifted into K. Every denominator contains the non-empty span.
template <typename T>
Vec4<T> de_boor(int degree, const T* K, T u, Vec4<T>* d) {
  for (int r = 1; r <= degree; ++r)
    for (int j = degree; j >= r; --j) {
      const T alpha = (u - K[j - 1]) / (K[j + degree - r] - K[j - 1]);
      for (int c = 0; c < 4; ++c) d[j][c] = (T(1) - alpha) * d[j - 1][c] + alpha * d[j][c];
    }
  return d[degree];
}

// 002 §3.3.3 on the CPU: the q+1 control rows around span_v evaluated as curves in u (pass 1),
// those curve points used as control points of a curve in v (pass 2), then the divide by w.
template <typename T>
Vec3<T> surface_point_de_boor(const SurfaceNet<T>& s, int span_u, T u, int span_v, T v) {
  T Ku[2 * kMaxDegree], Kv[2 * kMaxDegree];
  span_knots(s.degree_u, span_u, s.knots_u.data(), Ku);
  span_knots(s.degree_v, span_v, s.knots_v.data(), Kv);
  Vec4<T> curve[kMaxOrder], d[kMaxOrder];
  for (int l = 0; l <= s.degree_v; ++l) {
    for (int k = 0; k <= s.degree_u; ++k)
      d[k] = s.at(span_u - s.degree_u + k, span_v - s.degree_v + l);
    curve[l] = de_boor(s.degree_u, Ku, u, d);
  }
  const Vec4<T> p = de_boor(s.degree_v, Kv, v, curve);
  return {p[0] / p[3], p[1] / p[3], p[2] / p[3]};
}

}  // namespace nurbs::glsl_deboor
