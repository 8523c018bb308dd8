// The NURBS algorithms of Piegl & Tiller, "The NURBS Book" (2nd ed.), written once and templated
// on the scalar: the reference instantiates them in long double / __float128, cpu-coxdeboor in
// float / double, and the GPU strategies' shaders mirror them line by line.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <vector>

#include "reference/scalar.h"
#include "reference/surface.h"
#include "reference/validation.h"

namespace nurbs {

inline constexpr int kMaxOrder = kMaxDegree + 1;

// A2.1 FindSpan, with the convention that the end parameter (and anything past it) belongs to the
// last non-empty span, and anything before the start to the first. Exact comparisons only: an
// epsilon would pick the wrong span next to a knot. Returns s with knots[s] <= u < knots[s+1].
template <typename T>
int find_span(int degree, int count, const T* knots, T u) {
  if (!(u < knots[count])) {
    int s = count - 1;
    while (!(knots[s] < knots[s + 1])) --s;
    return s;
  }
  if (!(u > knots[degree])) u = knots[degree];
  // Last knot <= u in [degree, count]: the end of a run of equal knots, so the span is non-empty.
  const T* first_greater = std::upper_bound(knots + degree, knots + count + 1, u);
  return static_cast<int>(first_greater - knots) - 1;
}

// A2.2 BasisFuns: the degree+1 non-zero basis functions at u in span `span`, by the triangular
// Cox-de Boor scheme. No 0/0 can occur: every denominator spans the non-empty span.
template <typename T>
void basis_functions(int span, T u, int degree, const T* knots, T* basis) {
  T left[kMaxOrder], right[kMaxOrder];
  basis[0] = T(1);
  for (int j = 1; j <= degree; ++j) {
    left[j] = u - knots[span + 1 - j];
    right[j] = knots[span + j] - u;
    T saved = T(0);
    for (int r = 0; r < j; ++r) {
      const T temp = basis[r] / (right[r + 1] + left[j - r]);
      basis[r] = saved + right[r + 1] * temp;
      saved = left[j - r] * temp;
    }
    basis[j] = saved;
  }
}

// A2.3 DersBasisFuns: ders[k][j] = k-th derivative of the j-th non-zero basis function, for
// k = 0..n (rows above the degree are zero).
template <typename T>
void basis_function_derivatives(int span, T u, int degree, int n, const T* knots,
                                T (*ders)[kMaxOrder]) {
  T ndu[kMaxOrder][kMaxOrder], left[kMaxOrder], right[kMaxOrder];
  T a[2][kMaxOrder]{};  // zeroed only to quiet -Wmaybe-uninitialized: every read follows a write
  ndu[0][0] = T(1);
  for (int j = 1; j <= degree; ++j) {
    left[j] = u - knots[span + 1 - j];
    right[j] = knots[span + j] - u;
    T saved = T(0);
    for (int r = 0; r < j; ++r) {
      ndu[j][r] = right[r + 1] + left[j - r];  // lower triangle: knot differences
      const T temp = ndu[r][j - 1] / ndu[j][r];
      ndu[r][j] = saved + right[r + 1] * temp;  // upper triangle: basis functions
      saved = left[j - r] * temp;
    }
    ndu[j][j] = saved;
  }
  for (int j = 0; j <= degree; ++j) ders[0][j] = ndu[j][degree];
  for (int r = 0; r <= degree; ++r) {
    int s1 = 0, s2 = 1;
    a[0][0] = T(1);
    for (int k = 1; k <= n && k <= degree; ++k) {
      T d = T(0);
      const int rk = r - k, pk = degree - k;
      if (r >= k) {
        a[s2][0] = a[s1][0] / ndu[pk + 1][rk];
        d = a[s2][0] * ndu[rk][pk];
      }
      const int j1 = rk >= -1 ? 1 : -rk;
      const int j2 = (r - 1 <= pk) ? k - 1 : degree - r;
      for (int j = j1; j <= j2; ++j) {
        a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][rk + j];
        d += a[s2][j] * ndu[rk + j][pk];
      }
      if (r <= pk) {
        a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
        d += a[s2][k] * ndu[r][pk];
      }
      ders[k][r] = d;
      std::swap(s1, s2);
    }
  }
  int factor = degree;
  for (int k = 1; k <= n; ++k) {
    for (int j = 0; j <= degree; ++j) ders[k][j] = k <= degree ? ders[k][j] * T(factor) : T(0);
    factor *= degree - k;
  }
}

template <typename T>
using Vec3 = std::array<T, 3>;
template <typename T>
using Vec4 = std::array<T, 4>;

// One surface converted to the scalar T: knots, and control points in homogeneous form
// (w*x, w*y, w*z, w), as a device would hold them after upload.
template <typename T>
struct SurfaceNet {
  int degree_u = 0, degree_v = 0, count_u = 0, count_v = 0;
  std::vector<T> knots_u, knots_v;
  std::vector<Vec4<T>> homogeneous;  // (i, j) at i*count_v + j

  explicit SurfaceNet(const Surface& s)
      : degree_u(s.degree_u), degree_v(s.degree_v), count_u(s.count_u), count_v(s.count_v) {
    knots_u.assign(s.knots_u.begin(), s.knots_u.end());
    knots_v.assign(s.knots_v.begin(), s.knots_v.end());
    homogeneous.resize(s.points.size());
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      const T w = T(s.weights[k]);
      homogeneous[k] = {T(s.points[k][0]) * w, T(s.points[k][1]) * w, T(s.points[k][2]) * w, w};
    }
  }
  const Vec4<T>& at(int i, int j) const {
    return homogeneous[static_cast<std::size_t>(i) * count_v + j];
  }
  int span_u(T u) const { return find_span(degree_u, count_u, knots_u.data(), u); }
  int span_v(T v) const { return find_span(degree_v, count_v, knots_v.data(), v); }
};

// A4.3 SurfacePoint on the homogeneous net, given both spans and basis rows: the (p+1)(q+1)
// weighted sum, then the divide by w.
template <typename T>
Vec3<T> surface_point_from_basis(const SurfaceNet<T>& s, int span_u, const T* basis_u, int span_v,
                                 const T* basis_v) {
  Vec4<T> sum{};
  for (int k = 0; k <= s.degree_u; ++k) {
    Vec4<T> row{};
    for (int l = 0; l <= s.degree_v; ++l) {
      const Vec4<T>& p = s.at(span_u - s.degree_u + k, span_v - s.degree_v + l);
      for (int c = 0; c < 4; ++c) row[c] += basis_v[l] * p[c];
    }
    for (int c = 0; c < 4; ++c) sum[c] += basis_u[k] * row[c];
  }
  return {sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3]};
}

template <typename T>
Vec3<T> surface_point(const SurfaceNet<T>& s, T u, T v) {
  T basis_u[kMaxOrder], basis_v[kMaxOrder];
  const int su = s.span_u(u), sv = s.span_v(v);
  basis_functions(su, u, s.degree_u, s.knots_u.data(), basis_u);
  basis_functions(sv, v, s.degree_v, s.knots_v.data(), basis_v);
  return surface_point_from_basis(s, su, basis_u, sv, basis_v);
}

// A4.1 CurvePoint on homogeneous control points (w x, w y, w z, w): the p+1 weighted sum of span
// s, not yet divided by w (a caller in fewer dimensions or wanting the homogeneous point divides).
template <typename T>
Vec4<T> curve_point_homogeneous(int degree, int count, const T* knots, const Vec4<T>* homogeneous,
                                T u) {
  T basis[kMaxOrder];
  const int span = find_span(degree, count, knots, u);
  basis_functions(span, u, degree, knots, basis);
  Vec4<T> sum{};
  for (int k = 0; k <= degree; ++k) {
    const Vec4<T>& p = homogeneous[span - degree + k];
    for (int c = 0; c < 4; ++c) sum[c] += basis[k] * p[c];
  }
  return sum;
}

// skl[k][l] = d^(k+l) S / du^k dv^l for k + l <= order (order <= 2).
template <typename T>
struct SurfaceDerivatives {
  Vec3<T> skl[3][3]{};
};

// A3.6 SurfaceDerivsAlg1 on the homogeneous net, then A4.4 RatSurfaceDerivs.
template <typename T>
SurfaceDerivatives<T> surface_derivatives(const SurfaceNet<T>& s, T u, T v, int order) {
  T ders_u[3][kMaxOrder], ders_v[3][kMaxOrder];
  const int su = s.span_u(u), sv = s.span_v(v);
  basis_function_derivatives(su, u, s.degree_u, order, s.knots_u.data(), ders_u);
  basis_function_derivatives(sv, v, s.degree_v, order, s.knots_v.data(), ders_v);

  Vec4<T> aders[3][3]{};  // homogeneous derivatives
  for (int k = 0; k <= order; ++k) {
    for (int l = 0; l <= order - k; ++l) {
      Vec4<T> sum{};
      for (int i = 0; i <= s.degree_u; ++i) {
        Vec4<T> row{};
        for (int j = 0; j <= s.degree_v; ++j) {
          const Vec4<T>& p = s.at(su - s.degree_u + i, sv - s.degree_v + j);
          for (int c = 0; c < 4; ++c) row[c] += ders_v[l][j] * p[c];
        }
        for (int c = 0; c < 4; ++c) sum[c] += ders_u[k][i] * row[c];
      }
      aders[k][l] = sum;
    }
  }
  static constexpr int binomial[3][3] = {{1, 0, 0}, {1, 1, 0}, {1, 2, 1}};
  SurfaceDerivatives<T> out;
  const T w = aders[0][0][3];
  for (int k = 0; k <= order; ++k) {
    for (int l = 0; l <= order - k; ++l) {
      Vec3<T> v3{aders[k][l][0], aders[k][l][1], aders[k][l][2]};
      for (int j = 1; j <= l; ++j)
        for (int c = 0; c < 3; ++c)
          v3[c] -= T(binomial[l][j]) * aders[0][j][3] * out.skl[k][l - j][c];
      for (int i = 1; i <= k; ++i) {
        for (int c = 0; c < 3; ++c)
          v3[c] -= T(binomial[k][i]) * aders[i][0][3] * out.skl[k - i][l][c];
        for (int j = 1; j <= l; ++j)
          for (int c = 0; c < 3; ++c)
            v3[c] -=
                T(binomial[k][i]) * T(binomial[l][j]) * aders[i][j][3] * out.skl[k - i][l - j][c];
      }
      for (int c = 0; c < 3; ++c) out.skl[k][l][c] = v3[c] / w;
    }
  }
  return out;
}

template <typename T>
Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <typename T>
T norm(const Vec3<T>& a) {
  return scalar_sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

namespace detail {
// A cross product is trusted when it is not rounding noise: |a x b| above a small multiple of
// machine epsilon times (|a| + |b|)^2.
template <typename T>
bool normalize_if_resolved(Vec3<T> n, const Vec3<T>& a, const Vec3<T>& b, Vec3<T>& out) {
  const T scale = norm(a) + norm(b);
  const T length = norm(n);
  const T epsilon = scalar_epsilon<T>();
  if (!(length > T(1024) * epsilon * scale * scale) || !scalar_isfinite(length)) return false;
  for (int c = 0; c < 3; ++c) out[c] = n[c] / length;
  return true;
}
}  // namespace detail

// Unit normal Su x Sv. Where a tangent vanishes (a collapsed edge: sphere poles, the duck's and
// the teapot's degenerate patches) the normal is the limit along the surface: with Su = 0 on the
// edge v = v0, Su(u, v) ~ Suv (v - v0), so N ~ sign(v - v0) Suv x Sv; likewise for Sv = 0. Where
// that too vanishes, the normal of a neighbouring sample nudged toward the domain centre is used.
// Never NaN: if everything fails (a surface collapsed to a curve) the zero vector is returned.
template <typename T>
Vec3<T> surface_normal(const SurfaceNet<T>& s, T u, T v) {
  const T u0 = s.knots_u[s.degree_u], u1 = s.knots_u[s.count_u];
  const T v0 = s.knots_v[s.degree_v], v1 = s.knots_v[s.count_v];
  Vec3<T> n{};
  SurfaceDerivatives<T> d = surface_derivatives(s, u, v, 1);
  if (detail::normalize_if_resolved(cross(d.skl[1][0], d.skl[0][1]), d.skl[1][0], d.skl[0][1], n))
    return n;

  d = surface_derivatives(s, u, v, 2);
  const Vec3<T>&su = d.skl[1][0], &sv = d.skl[0][1], &suv = d.skl[1][1];
  const bool su_vanishes = norm(su) <= norm(sv);
  if (su_vanishes) {
    const T side = (v - v0) <= (v1 - v) ? T(1) : T(-1);
    Vec3<T> limit = cross(suv, sv);
    for (T& c : limit) c *= side;
    if (detail::normalize_if_resolved(limit, suv, sv, n)) return n;
  } else {
    const T side = (u - u0) <= (u1 - u) ? T(1) : T(-1);
    Vec3<T> limit = cross(su, suv);
    for (T& c : limit) c *= side;
    if (detail::normalize_if_resolved(limit, su, suv, n)) return n;
  }
  const T mid_u = (u0 + u1) / T(2), mid_v = (v0 + v1) / T(2);
  for (T step = T(1) / T(4096); step <= T(1) / T(4); step *= T(8)) {
    const T nu = u + (mid_u - u) * step, nv = v + (mid_v - v) * step;
    d = surface_derivatives(s, nu, nv, 1);
    if (detail::normalize_if_resolved(cross(d.skl[1][0], d.skl[0][1]), d.skl[1][0], d.skl[0][1], n))
      return n;
  }
  return Vec3<T>{};
}

}  // namespace nurbs
