// The C++ builds of the single-source de Boor (strategies/glsl_deboor/de_boor_source.h): float as
// de_boor.frag runs it, double and long double for the tests; and 002 §3.3.3's two-pass
// composition on the CPU, the one the tests check against nurbs::surface_point.
#pragma once

#include "reference/nurbs_math.h"

namespace nurbs::glsl_deboor {

namespace source {
#define DB_REAL float
#include "strategies/glsl_deboor/de_boor_source.h"
#undef DB_REAL
#define DB_REAL double
#include "strategies/glsl_deboor/de_boor_source.h"
#undef DB_REAL
#define DB_REAL long double
#include "strategies/glsl_deboor/de_boor_source.h"
#undef DB_REAL
}  // namespace source

// The 2p knots de Boor reads for span `span` of a degree-p knot vector.
template <typename T>
void span_knots(int degree, int span, const T* knots, T* K) {
  for (int t = 0; t < 2 * degree; ++t) K[t] = knots[span - degree + 1 + t];
}

// d[0..p] = the p+1 homogeneous control points P_{span-p} .. P_span on entry; returns C(u).
template <typename T>
Vec4<T> de_boor(int degree, const T* K, T u, Vec4<T>* d) {
  return source::db_de_boor(degree, K, u, d);
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
