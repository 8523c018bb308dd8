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

}  // namespace nurbs::horner
