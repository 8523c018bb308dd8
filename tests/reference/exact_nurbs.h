// An exact NURBS evaluator in rational arithmetic (GMP mpq), written independently of
// reference/nurbs_math.h to check it: the recursive Cox-de Boor DEFINITION over all basis
// functions (not the triangular A2.2 scheme), with 0/0 := 0, derivatives by differentiating the
// recursion (P&T eq. 2.9), the sum over ALL control points, then the rational quotient rule.
// Doubles (and long doubles, __float128s) convert to rationals exactly, so every error measured
// against it is the error of the code under test alone.
#pragma once

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <vector>

#include "reference/scalar.h"
#include "reference/surface.h"

namespace nurbs::test {

using Q = mpq_class;
using QVec3 = std::array<Q, 3>;

inline Q to_q(double x) {
  return Q(x);
}  // mpq_set_d is exact

inline Q mantissa_to_q(const mpz_class& mantissa, long exponent) {
  Q q(mantissa);
  if (exponent >= 0)
    mpq_mul_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(exponent));
  else
    mpq_div_2exp(q.get_mpq_t(), q.get_mpq_t(), static_cast<mp_bitcnt_t>(-exponent));
  return q;
}

inline Q to_q(long double x) {
  if (!std::isfinite(x)) throw std::domain_error("to_q: not finite");
  if (x == 0) return Q(0);
  int e = 0;
  const long double m = std::frexp(std::fabs(x), &e);  // [0.5, 1)
  static_assert(sizeof(unsigned long) == 8, "64-bit unsigned long expected (LP64)");
  const auto bits = static_cast<unsigned long>(std::ldexp(m, 64));  // exact: 64-bit mantissa
  Q q = mantissa_to_q(mpz_class(bits), static_cast<long>(e) - 64);
  return x < 0 ? Q(-q) : q;
}

#if NURBSBENCH_HAS_FLOAT128
inline Q to_q(float128 x) {
  if (!finiteq(x)) throw std::domain_error("to_q: not finite");
  if (x == 0) return Q(0);
  int e = 0;
  const float128 m = ldexpq(frexpq(fabsq(x), &e), 113);  // integer < 2^113, exact
  const float128 two64 = ldexpq(1, 64);
  const float128 hi = floorq(m / two64);  // < 2^49
  const float128 lo = m - hi * two64;     // < 2^64, exact
  mpz_class z(static_cast<unsigned long>(hi));
  z <<= 64;
  z += mpz_class(static_cast<unsigned long>(lo));
  Q q = mantissa_to_q(z, static_cast<long>(e) - 113);
  return x < 0 ? Q(-q) : q;
}
#endif

inline double to_d(const Q& q) {
  return q.get_d();
}
inline Q abs_q(const Q& q) {
  return q < 0 ? Q(-q) : q;
}

// Which one-sided limit at a knot: `right` uses the span [k_s, k_s+1) containing u (the
// reference's convention), except that u_max belongs to the last non-empty span; `left` uses
// (k_s, k_s+1], except that u_min belongs to the first non-empty span.
enum class Side { right, left };

// The span index the rule selects, by a linear scan over the domain's spans.
inline int exact_span(const std::vector<Q>& knots, int degree, int count, const Q& u, Side side) {
  int first = -1, last = -1;
  for (int s = degree; s < count; ++s)
    if (knots[s] < knots[s + 1]) {
      if (first < 0) first = s;
      last = s;
    }
  if (first < 0) throw std::invalid_argument("exact_span: empty domain");
  if (u < knots[degree] || u > knots[count])
    throw std::invalid_argument("exact_span: parameter outside the domain");
  for (int s = degree; s < count; ++s) {
    if (!(knots[s] < knots[s + 1])) continue;
    if (side == Side::right && knots[s] <= u && u < knots[s + 1]) return s;
    if (side == Side::left && knots[s] < u && u <= knots[s + 1]) return s;
  }
  return side == Side::right ? last : first;
}

// ders[k][i] = k-th derivative of N_{i,degree} at u, i = 0..count-1, k = 0..max_order, from the
// recursive definition: N_{i,0} = 1 on the selected span, else 0;
// N_{i,q} = (u - k_i)/(k_{i+q} - k_i) N_{i,q-1} + (k_{i+q+1} - u)/(k_{i+q+1} - k_{i+1}) N_{i+1,q-1}
// and N^(r)_{i,q} = q (N^(r-1)_{i,q-1}/(k_{i+q} - k_i) - N^(r-1)_{i+1,q-1}/(k_{i+q+1} - k_{i+1})),
// every term with a zero denominator taken as 0.
inline std::vector<std::vector<Q>> exact_basis(const std::vector<Q>& knots, int degree, int count,
                                               const Q& u, int max_order, Side side) {
  const int m = static_cast<int>(knots.size()) - 1;  // intervals [k_i, k_i+1], i = 0..m-1
  const int span = exact_span(knots, degree, count, u, side);
  // level[q][i] = N_{i,q}(u) for i = 0..m-1-q
  std::vector<std::vector<Q>> level(degree + 1);
  level[0].assign(m, Q(0));
  level[0][span] = 1;
  for (int q = 1; q <= degree; ++q) {
    level[q].assign(m - q, Q(0));
    for (int i = 0; i < m - q; ++i) {
      Q value = 0;
      const Q d1 = knots[i + q] - knots[i], d2 = knots[i + q + 1] - knots[i + 1];
      if (d1 != 0 && level[q - 1][i] != 0) value += (u - knots[i]) / d1 * level[q - 1][i];
      if (d2 != 0 && level[q - 1][i + 1] != 0)
        value += (knots[i + q + 1] - u) / d2 * level[q - 1][i + 1];
      level[q][i] = value;
    }
  }
  // derivative(r, q)[i] = N^(r)_{i,q}
  auto derivative = [&](auto&& self, int r, int q) -> std::vector<Q> {
    if (r == 0) return level[q];
    std::vector<Q> out(m - q, Q(0));
    if (q == 0) return out;
    const std::vector<Q> lower = self(self, r - 1, q - 1);
    for (int i = 0; i < m - q; ++i) {
      Q value = 0;
      const Q d1 = knots[i + q] - knots[i], d2 = knots[i + q + 1] - knots[i + 1];
      if (d1 != 0) value += lower[i] / d1;
      if (d2 != 0) value -= lower[i + 1] / d2;
      out[i] = Q(q) * value;
    }
    return out;
  };
  std::vector<std::vector<Q>> ders(max_order + 1);
  for (int r = 0; r <= max_order; ++r) {
    std::vector<Q> all = derivative(derivative, r, degree);
    ders[r].assign(all.begin(), all.begin() + count);
  }
  return ders;
}

struct ExactSurface {
  int degree_u, degree_v, count_u, count_v;
  std::vector<Q> knots_u, knots_v;
  std::vector<std::array<Q, 4>> homogeneous;  // (w x, w y, w z, w), (i, j) at i * count_v + j

  explicit ExactSurface(const Surface& s)
      : degree_u(s.degree_u), degree_v(s.degree_v), count_u(s.count_u), count_v(s.count_v) {
    for (double k : s.knots_u) knots_u.push_back(to_q(k));
    for (double k : s.knots_v) knots_v.push_back(to_q(k));
    for (std::size_t k = 0; k < s.points.size(); ++k) {
      const Q w = to_q(s.weights[k]);
      homogeneous.push_back(
          {to_q(s.points[k][0]) * w, to_q(s.points[k][1]) * w, to_q(s.points[k][2]) * w, w});
    }
  }
};

// skl[k][l] = d^(k+l) S / du^k dv^l for k + l <= order (order <= 2), as in the reference.
struct ExactDerivatives {
  QVec3 skl[3][3];
};

// Basis rows of one parameter: ders[k][i], k = 0..order, i = 0..count-1.
using ExactBasis = std::vector<std::vector<Q>>;

inline ExactBasis exact_basis_u(const ExactSurface& s, const Q& u, int order,
                                Side side = Side::right) {
  return exact_basis(s.knots_u, s.degree_u, s.count_u, u, order, side);
}
inline ExactBasis exact_basis_v(const ExactSurface& s, const Q& v, int order,
                                Side side = Side::right) {
  return exact_basis(s.knots_v, s.degree_v, s.count_v, v, order, side);
}

// From precomputed basis rows (a tensor grid needs NU + NV of them, not NU * NV).
inline ExactDerivatives exact_derivatives(const ExactSurface& s, const ExactBasis& nu,
                                          const ExactBasis& nv, int order) {
  if (order < 0 || order > 2 || static_cast<int>(nu.size()) <= order ||
      static_cast<int>(nv.size()) <= order)
    throw std::invalid_argument("exact_derivatives: order 0..2, basis rows up to it");
  // Homogeneous derivatives A_kl (xyz) and W_kl, summed over every control point.
  std::array<Q, 4> a[3][3];
  for (int k = 0; k <= order; ++k)
    for (int l = 0; l <= order - k; ++l) {
      std::array<Q, 4> sum{Q(0), Q(0), Q(0), Q(0)};
      for (int i = 0; i < s.count_u; ++i) {
        if (nu[k][i] == 0) continue;
        std::array<Q, 4> row{Q(0), Q(0), Q(0), Q(0)};
        for (int j = 0; j < s.count_v; ++j) {
          if (nv[l][j] == 0) continue;
          const auto& p = s.homogeneous[static_cast<std::size_t>(i) * s.count_v + j];
          for (int c = 0; c < 4; ++c) row[c] += nv[l][j] * p[c];
        }
        for (int c = 0; c < 4; ++c) sum[c] += nu[k][i] * row[c];
      }
      a[k][l] = sum;
    }
  // Quotient rule, written out per derivative (not the A4.4 loop).
  ExactDerivatives out;
  const Q& w = a[0][0][3];
  for (int c = 0; c < 3; ++c) {
    const Q s00 = a[0][0][c] / w;
    out.skl[0][0][c] = s00;
    if (order >= 1) {
      const Q s10 = (a[1][0][c] - a[1][0][3] * s00) / w;
      const Q s01 = (a[0][1][c] - a[0][1][3] * s00) / w;
      out.skl[1][0][c] = s10;
      out.skl[0][1][c] = s01;
      if (order >= 2) {
        out.skl[2][0][c] = (a[2][0][c] - 2 * a[1][0][3] * s10 - a[2][0][3] * s00) / w;
        out.skl[0][2][c] = (a[0][2][c] - 2 * a[0][1][3] * s01 - a[0][2][3] * s00) / w;
        out.skl[1][1][c] =
            (a[1][1][c] - a[1][0][3] * s01 - a[0][1][3] * s10 - a[1][1][3] * s00) / w;
      }
    }
  }
  return out;
}

inline ExactDerivatives exact_derivatives(const ExactSurface& s, const Q& u, const Q& v, int order,
                                          Side side_u = Side::right, Side side_v = Side::right) {
  return exact_derivatives(s, exact_basis_u(s, u, order, side_u),
                           exact_basis_v(s, v, order, side_v), order);
}

inline QVec3 exact_point(const ExactSurface& s, const Q& u, const Q& v) {
  return exact_derivatives(s, u, v, 0).skl[0][0];
}

// Sum over i of |N^(k)_i(u)| (exact), the scale of the rounding error in a k-th derivative.
inline Q abs_sum(const std::vector<Q>& values) {
  Q sum = 0;
  for (const Q& x : values) sum += abs_q(x);
  return sum;
}

}  // namespace nurbs::test

namespace nurbs::test {

// max over components of |got - exact|, computed exactly, returned as a double.
template <typename T>
double max_abs_error(const std::array<T, 3>& got, const QVec3& exact) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) worst = std::max(worst, to_d(abs_q(to_q(got[c]) - exact[c])));
  return worst;
}

// The spacing of doubles at |x| (x rounded toward zero first), i.e. one ulp of the double interval
// holding x: a correctly rounded result is within half of it.
inline double double_ulp(const Q& x) {
  const double d = std::fabs(to_d(x));
  if (d == 0) return std::numeric_limits<double>::denorm_min();
  return std::nextafter(d, std::numeric_limits<double>::infinity()) - d;
}

// Largest |coordinate| and max/min weight of a surface's control net.
inline double largest_coordinate(const Surface& s) {
  double largest = 0;
  for (const Point3& p : s.points)
    for (double c : p) largest = std::max(largest, std::fabs(c));
  return largest;
}
inline double weight_ratio(const Surface& s) {
  const auto [lo, hi] = std::minmax_element(s.weights.begin(), s.weights.end());
  return *hi / *lo;
}

}  // namespace nurbs::test
