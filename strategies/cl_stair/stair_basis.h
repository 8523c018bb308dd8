// The RPNS "stair" basis (003 §3.2), written once in C++ and mirrored line by line by
// stair.cl (each kernel function names the function here it copies).
//
// Derivation. On a non-empty span [x_i, x_i+1) the Cox-de Boor recursion (003 eq. 1) is a sum
// over lattice paths in the triangular table from N_{i-k,p} down to N_{i,0}: a "left" step
// N_{a,c} -> N_{a,c-1} carries (u - x_a)/(x_{a+c} - x_a), a "right" step N_{a,c} -> N_{a+1,c-1}
// carries (x_{a+c+1} - u)/(x_{a+c+1} - x_{a+1}). A path from N_{i-k,p} takes k right and p-k left
// steps, so it stays in a (p-k) x k rectangle (the paper's "rectangle table", Fig. 7) until it
// reaches either
//   the column  N_{i,c}   (all k right steps done):  N_{i,c}   = (u - x_i)^c     * A_c,
//                                                     A_c = 1 / prod_{l=1..c} (x_{i+l} - x_i)
//   the diagonal N_{i-d,d} (all p-k left steps done): N_{i-d,d} = (x_{i+1} - u)^d * B_d,
//                                                     B_d = 1 / prod_{l=1..d} (x_{i+1} - x_{i+1-l})
// whose values on this span are the closed forms above (their only path left is straight).
// Hence N_{i-k,p} = sum_r T_r * L * N_{i-k+r, k-r} + sum_l T_l * R * N_{i, p-k-l}, where T is the
// sum over the paths inside the rectangle to the node before the boundary: the paper's two sums.
//
// Where the paper's text is ambiguous or wrong, and what we chose:
//  * The printed coefficient of each boundary term is ONE product, e.g.
//    (u - x_{i-k+j})^{p-k} (x_{i+k-1+j} - u)^j / prod_{l=1}^{p-k+j} (x_{i+l} - x_{i-k+j}). That is
//    the sum over the rectangle's paths only when a single path reaches the boundary node, which
//    holds for every k when p <= 3 (tests: exact in rational arithmetic, stair_printed_formula
//    below) and fails from p = 4 (e.g. k = 2: the paths L-R-R and R-L-R both reach N_{i,1}). The
//    paper's second display (x_{i+p-1+j}, x_{i+p-k+1+j}) is already wrong at p = 3.
//  * We therefore keep the paper's structure -- closed-form column and diagonal functions, all
//    denominators per-span constants computed once per KSQuad -- and compute the coefficients T
//    exactly by accumulating the rectangle table row by row (O(k(p-k)) per function instead of
//    the paper's O(p); identical to the printed products for p <= 3).
//  * The per-span constants: R[s][t] = 1 / (x_{i+1+t} - x_{i-s}), s, t = 0..p-1. Every
//    denominator of the rectangle, A_c and B_d is one of them or a product of them (all > 0 on a
//    non-empty span: x_{i-s} <= x_i < x_{i+1} <= x_{i+1+t}), so no 0/0 can occur.
//  * Every difference the per-sample work takes, u - x_{i-s} and x_{i+1+t} - u, is >= 0 on the
//    span: the form has products of differences and powers, no subtraction of products.
#pragma once

#include "reference/nurbs_math.h"

namespace nurbs {

inline constexpr int kStairMaxDegree = 9;  // local-memory arrays of the kernel are sized for it

// The constants of one direction of one KSQuad (003 §3.2: "computed only once").
template <typename T>
struct StairConstants {
  T knots[2 * kStairMaxDegree];           // x_{i-p+1} .. x_{i+p}
  T r[kStairMaxDegree][kStairMaxDegree];  // r[s][t] = 1 / (x_{i+1+t} - x_{i-s})
  T column[kStairMaxDegree + 1];          // A_c, c = 0..p (A_0 = 1)
  T diagonal[kStairMaxDegree + 1];        // B_d, d = 0..p (B_0 = 1)
};

// stair.cl: stair_constants. `knots` is the whole knot vector, `span` = i.
template <typename T>
void stair_constants(int span, int degree, const T* knots, StairConstants<T>& c) {
  const int p = degree;
  for (int t = 0; t < 2 * p; ++t) c.knots[t] = knots[span - p + 1 + t];
  // x_{i-s} = c.knots[p-1-s], x_{i+1+t} = c.knots[p+t]
  for (int s = 0; s < p; ++s)
    for (int t = 0; t < p; ++t) c.r[s][t] = T(1) / (c.knots[p + t] - c.knots[p - 1 - s]);
  c.column[0] = T(1);
  c.diagonal[0] = T(1);
  for (int l = 1; l <= p; ++l) {
    c.column[l] = c.column[l - 1] * c.r[0][l - 1];      // 1/(x_{i+l} - x_i)
    c.diagonal[l] = c.diagonal[l - 1] * c.r[l - 1][0];  // 1/(x_{i+1} - x_{i+1-l})
  }
}

// stair.cl: stair_basis. basis[j] = N_{i-p+j,p}(u), j = 0..p (the order of A2.2).
// `knot_degree` (default: `degree`) is the degree `c` was built for: a lower degree reuses the
// constants -- r, A and B belong to the span alone, only the knot window moves (stair_derivative).
template <typename T>
void stair_basis(const StairConstants<T>& c, int degree, T u, T* basis, int knot_degree = -1) {
  const int p = degree;
  const int o = knot_degree < 0 ? p : knot_degree;     // x_{i-s} = c.knots[o-1-s]
  T dl[kStairMaxDegree + 1], dr[kStairMaxDegree + 1];  // u - x_{i-s}, x_{i+1+t} - u
  for (int s = 0; s < p; ++s) {
    dl[s] = u - c.knots[o - 1 - s];
    dr[s] = c.knots[o + s] - u;
  }
  // Column and diagonal functions by their closed forms: col[m] = N_{i,m}, diag[m] = N_{i-m,m}.
  T col[kStairMaxDegree + 1], diag[kStairMaxDegree + 1];
  col[0] = T(1);
  diag[0] = T(1);
  T pow_l = T(1), pow_r = T(1);
  for (int m = 1; m <= p; ++m) {
    pow_l *= dl[0];
    pow_r *= dr[0];
    col[m] = pow_l * c.column[m];
    diag[m] = pow_r * c.diagonal[m];
  }
  basis[p] = col[p];   // k = 0: N_{i,p}
  basis[0] = diag[p];  // k = p: N_{i-p,p}
  for (int k = 1; k < p; ++k) {
    // Rectangle row r (r right steps taken), column l (l left steps): node N_{i-k+r, p-r-l}.
    // left step from (r, l):  dl[k-r] * r[k-r][p-k-l-1];  right step: dr[p-k-l] * r[k-r-1][p-k-l]
    const int w = p - k;
    T t[kStairMaxDegree];
    T sum = T(0);
    for (int r = 0; r < k; ++r) {
      for (int l = 0; l < w; ++l) {
        const T from_above = r > 0 ? t[l] * (dr[w - l] * c.r[k - r][w - l]) : T(l == 0 ? 1 : 0);
        const T from_left = l == 0 ? T(0) : t[l - 1] * (dl[k - r] * c.r[k - r][w - l]);
        t[l] = from_above + from_left;
      }
      // left step off the last column of the row lands on the diagonal N_{i-k+r, k-r}
      sum += t[w - 1] * (dl[k - r] * c.r[k - r][0]) * diag[k - r];
    }
    // right step off the last row lands on the column N_{i, p-k-l}
    for (int l = 0; l < w; ++l) sum += t[l] * (dr[w - l] * c.r[0][w - l]) * col[w - l];
    basis[p - k] = sum;
  }
}

// vk-ksquad's ksquad.tese: stair_derivative. derivative[j] = d/du N_{i-p+j,p}(u), j = 0..p, by
// Piegl & Tiller eq. (2.7) on the degree p-1 stair basis of the same span:
//   N'_{i-p+j,p} = p (N_{i-p+j,p-1} / (x_{i+j} - x_{i-p+j}) - N_{i-p+j+1,p-1} / (x_{i+j+1} -
//   x_{i-p+j+1}))
// where N_{i-p+j,p-1} is lower[j-1] (zero outside 0..p-1) and both denominators are per-span
// constants: 1 / (x_{i+j} - x_{i-p+j}) = r[p-j][j-1].
template <typename T>
void stair_derivative(const StairConstants<T>& c, int degree, T u, T* derivative) {
  const int p = degree;
  T lower[kStairMaxDegree + 1];
  stair_basis(c, p - 1, u, lower, p);
  for (int j = 0; j <= p; ++j) {
    const T left = j >= 1 ? lower[j - 1] * c.r[p - j][j - 1] : T(0);
    const T right = j <= p - 1 ? lower[j] * c.r[p - j - 1][j] : T(0);
    derivative[j] = T(p) * (left - right);
  }
}

}  // namespace nurbs
