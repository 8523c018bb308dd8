// Macri 1999 (004, "Equation 6" and ComputeBasisCoefficients): on one knot span every non-zero
// B-spline basis function is a polynomial of degree p, so its power-basis coefficients can be
// computed once per knot vector and the basis evaluated by Horner's rule, derivatives from the
// same coefficients.
//
// The polynomials are expanded about an origin: 0 (Macri's A0 + A1 u + ... + An u^n, exactly his
// formula) or the span's left knot (t = u - u_s). Expanding about 0 loses digits as the degree
// grows and as the span moves away from 0 (catastrophic cancellation between large coefficients);
// the span-local origin keeps every term of order one. The conversion itself is done in long
// double by the Cox-de Boor recursion on polynomials, then rounded once to the evaluation scalar.
#pragma once

#include <cstddef>
#include <vector>

namespace nurbs::horner {

enum class Origin { span_start, zero };

// Coefficients of the p+1 non-zero basis functions N_{span-p+k} (k = 0..p) on knot span `span`,
// as polynomials in t = u - origin: c[j * (p+1) + k] multiplies t^j. `span` must be non-empty.
std::vector<long double> power_basis_coefficients(const std::vector<double>& knots, int degree,
                                                  int span, long double origin);

// The basis (and optional first derivatives) at t from coefficients laid out as above, by
// Horner's rule; vectorised across k.
template <typename T>
inline void horner_basis(const T* c, int degree, T t, T* values, T* ders) {
  const int order = degree + 1;
  for (int k = 0; k < order; ++k) values[k] = c[degree * order + k];
  for (int j = degree - 1; j >= 0; --j)
    for (int k = 0; k < order; ++k) values[k] = values[k] * t + c[j * order + k];
  if (!ders) return;
  for (int k = 0; k < order; ++k) ders[k] = T(degree) * c[degree * order + k];
  for (int j = degree - 1; j >= 1; --j)
    for (int k = 0; k < order; ++k) ders[k] = ders[k] * t + T(j) * c[j * order + k];
}

// Forward differences, 004's alternative for EvaluateBasisFunctions ("using a technique called
// 'forward differences' to eliminate the multiplications in the inner loop"): `lanes`
// polynomials of degree `degree` in t (coefficients c[j * lanes + l] of t^j), at the steps
// t = offset + i * step, i = 0..steps-1, with `degree` additions per lane per step, written to
// out[i * lanes + l] in T.
// The starting difference table is computed exactly-ish in long double and rounded once per
// entry; only the additions run in T. Differences of values cancel catastrophically (the j-th
// difference is O(step^j) out of O(1) values: in T they lost everything within a few dozen steps,
// measured 5e3 f32 ulps on patch144 at 257x257, and even long double cannot hold the 15th), so
// they come from the Taylor coefficients instead: with g(i) = f(offset + i step) = sum_m b_m i^m,
// b_m = step^m f^(m)(offset) / m!, the j-th difference at 0 is j! sum_(m>=j) S(m, j) b_m (S: the
// Stirling numbers of the second kind), dominated by its first term. The additions' rounding still
// grows with the steps and the degree (tests/strategies/cpu_horner: the bound and the errors).
template <typename T>
void forward_differences(const long double* c, int degree, int lanes, long double offset,
                         long double step, int steps, T* out) {
  const int rows = degree + 1;
  // Stirling numbers of the second kind, S(m, j), m, j <= degree.
  std::vector<long double> stirling(static_cast<std::size_t>(rows) * rows, 0.0L);
  stirling[0] = 1;
  for (int m = 1; m <= degree; ++m)
    for (int j = 1; j <= m; ++j)
      stirling[m * rows + j] = j * stirling[(m - 1) * rows + j] + stirling[(m - 1) * rows + j - 1];
  std::vector<T> d(static_cast<std::size_t>(rows) * lanes);
  std::vector<long double> taylor(rows);
  for (int l = 0; l < lanes; ++l) {
    // Taylor shift to `offset` (repeated synthetic division), then scale by step^m.
    for (int j = 0; j <= degree; ++j) taylor[j] = c[j * lanes + l];
    for (int m = 0; m < degree; ++m)
      for (int j = degree - 1; j >= m; --j) taylor[j] += offset * taylor[j + 1];
    long double power = 1;
    for (int m = 0; m <= degree; ++m, power *= step) taylor[m] *= power;
    long double factorial = 1;
    for (int j = 0; j <= degree; ++j) {
      if (j > 0) factorial *= j;
      long double sum = 0;
      for (int m = degree; m >= j; --m) sum += stirling[m * rows + j] * taylor[m];
      d[j * lanes + l] = T(factorial * sum);
    }
  }
  for (int i = 0; i < steps; ++i) {
    for (int l = 0; l < lanes; ++l) out[static_cast<std::size_t>(i) * lanes + l] = d[l];
    for (int j = 0; j < degree; ++j)
      for (int l = 0; l < lanes; ++l) d[j * lanes + l] += d[(j + 1) * lanes + l];
  }
}

}  // namespace nurbs::horner
