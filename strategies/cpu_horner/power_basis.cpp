#include "strategies/cpu_horner/power_basis.h"

#include <cstddef>

namespace nurbs::horner {

std::vector<long double> power_basis_coefficients(const std::vector<double>& knots, int degree,
                                                  int span, long double origin) {
  const int order = degree + 1;
  // poly[i][j]: coefficient of t^j of N_{span-d+i, d} at the current degree d (i = 0..d).
  std::vector<std::vector<long double>> poly(order, std::vector<long double>(order, 0.0L));
  poly[0][0] = 1.0L;  // N_{span,0} = 1 on the span
  auto knot = [&](int i) { return static_cast<long double>(knots[static_cast<std::size_t>(i)]); };
  for (int d = 1; d <= degree; ++d) {
    std::vector<std::vector<long double>> next(order, std::vector<long double>(order, 0.0L));
    for (int i = 0; i <= d; ++i) {
      const int g = span - d + i;  // global index of N_{g,d}
      // N_{g,d} = (u - u_g)/(u_{g+d} - u_g) N_{g,d-1} + (u_{g+d+1} - u)/(u_{g+d+1} - u_{g+1})
      // N_{g+1,d-1}, with 0/0 = 0; N_{g,d-1} is poly[i-1], N_{g+1,d-1} is poly[i] (when in range).
      if (i >= 1) {
        const long double den = knot(g + d) - knot(g);
        if (den != 0) {
          const long double a = 1.0L / den, b = (origin - knot(g)) / den;  // (t + o - u_g)/den
          for (int j = 0; j < d; ++j) {
            next[i][j + 1] += a * poly[i - 1][j];
            next[i][j] += b * poly[i - 1][j];
          }
        }
      }
      if (i <= d - 1) {
        const long double den = knot(g + d + 1) - knot(g + 1);
        if (den != 0) {
          const long double a = -1.0L / den, b = (knot(g + d + 1) - origin) / den;
          for (int j = 0; j < d; ++j) {
            next[i][j + 1] += a * poly[i][j];
            next[i][j] += b * poly[i][j];
          }
        }
      }
    }
    poly.swap(next);
  }
  std::vector<long double> c(static_cast<std::size_t>(order) * order);
  for (int k = 0; k < order; ++k)
    for (int j = 0; j < order; ++j) c[static_cast<std::size_t>(j) * order + k] = poly[k][j];
  return c;
}

}  // namespace nurbs::horner
