// The RPNS "stair" basis (003 §3.2), written ONCE in the common subset of C++, OpenCL C and GLSL
// (the way OpenSubdiv's osd/patchBasisCommon.h serves its evaluators): compiled as C++ by
// strategies/stair_basis/stair.h (float, double, long double), as OpenCL C by cl-stair
// (prepended to stair.cl at run time) and as GLSL by vk-ksquad's ksquad.tese and the test's
// compute shader (#include). The few differences are the macros below. No include guard in C++:
// stair.h includes it once per scalar type.
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
//    holds for every k when p <= 3 (tests/strategies/stair_basis/stair_basis_test.cpp,
//    PrintedFormulaHoldsUpToDegree3Only) and fails from p = 4 (e.g. k = 2: the paths L-R-R
//    and R-L-R both reach N_{i,1}). The paper's second display (x_{i+p-1+j}, x_{i+p-k+1+j}) is
//    already wrong at p = 3.
//  * We therefore keep the paper's structure -- closed-form column and diagonal functions, all
//    denominators per-span constants computed once per KSQuad -- and compute the coefficients T
//    exactly by accumulating the rectangle table row by row (O(k(p-k)) per function instead of
//    the paper's O(p); identical to the printed products for p <= 3).
//  * The per-span constants: R[s][t] = 1 / (x_{i+1+t} - x_{i-s}), s, t = 0..p-1. Every
//    denominator of the rectangle, A_c and B_d is one of them or a product of them (all > 0 on a
//    non-empty span: x_{i-s} <= x_i < x_{i+1} <= x_{i+1+t}), so no 0/0 can occur.
//  * Every difference the per-sample work takes, u - x_{i-s} and x_{i+1+t} - u, is >= 0 on the
//    span: the form has products of differences and powers, no subtraction of products.
//  * The closed forms are evaluated in the span's own scale, h = x_{i+1} - x_i:
//    N_{i,c} = ((u - x_i)/h)^c * A_c h^c, N_{i-d,d} = ((x_{i+1} - u)/h)^d * B_d h^d, the same
//    values. As printed, A_c = 1/prod(x_{i+l} - x_i) overflows float where a span is short and
//    the degree high (real models: a degree-10 direction with 2.3e-6-wide spans of multiplicity
//    9, linkrods.step, gives A_10 ~ 1e56) and (u - x_i)^c underflows, 0 * inf = NaN; scaled,
//    every factor lies in [0, 1]. A span empty in the working precision (two knots that round
//    to one float) has no scale: callers choose spans by a search over the rounded knots
//    (reference/nurbs_math.h find_span), which never returns one.
//
// The constants of one direction of one span ("computed only once", 003 §3.2) are SB_CONSTANT_REALS
// packed reals, the layout every language reads (vk-ksquad uploads the C++ build's):
//   SB_KNOTS    + t, t = 0..2p-1       x_{i-p+1} .. x_{i+p}
//   SB_R        + s * SB_MAX_DEG + t   r[s][t] = 1 / (x_{i+1+t} - x_{i-s}), s, t = 0..p-1
//   SB_COLUMN   + c, c = 0..p          A_c h^c (= 1 at c = 0)
//   SB_DIAGONAL + d, d = 0..p          B_d h^d (= 1 at d = 0)

#if defined(__cplusplus) || defined(GL_GOOGLE_include_directive)
#include "../kernel_language/kernel_language.h"
#endif
#if !defined(KL_GLSL)
// C++: the includer defines SB_REAL (float, double or long double). OpenCL: the build options
// define SB_REAL (and enable cl_khr_fp64 for double); the constants live in local memory (one
// copy per work-group, cl-stair), the knots in global memory.
#define SB_CONSTS KL_LOCAL const SB_REAL*
#define SB_CONSTS_OUT KL_LOCAL SB_REAL*
#define SB_KNOTS_IN KL_GLOBAL const SB_REAL*
#define SB_C(c, i) (c)[i]
#define SB_C_OUT(c, i) (c)[i]
#define SB_KNOT_IN(k, i) (k)[i]
#else
// GLSL: a function cannot take a buffer as a parameter, so the includer declares the storage
// buffer `consts` (float) and a set of constants is its offset there. stair_constants is
// compiled where the includer defines SB_GLSL_CONSTANTS and declares a writable `consts` and an
// `sb_knots` buffer (float; a knot vector is its offset there): vk-ksquad's constants pass,
// ksquad_constants.comp.
#define SB_REAL float
#define SB_CONSTS int
#define SB_CONSTS_OUT int
#define SB_KNOTS_IN int
#define SB_C(c, i) consts[(c) + (i)]
#define SB_C_OUT(c, i) consts[(c) + (i)]
#define SB_KNOT_IN(k, i) sb_knots[(k) + (i)]
#endif

// reference/validation.h kMaxDegree: the largest degree any scene may have.
#define SB_MAX_DEG 15
#define SB_MAX_ORDER (SB_MAX_DEG + 1)
#define SB_KNOTS 0
#define SB_R (2 * SB_MAX_DEG)
#define SB_COLUMN (SB_R + SB_MAX_DEG * SB_MAX_DEG)
#define SB_DIAGONAL (SB_COLUMN + SB_MAX_ORDER)
#define SB_CONSTANT_REALS (SB_DIAGONAL + SB_MAX_ORDER)
#define SB_KNOT(c, t) SB_C(c, SB_KNOTS + (t))
#define SB_RS(c, s, t) SB_C(c, SB_R + (s)*SB_MAX_DEG + (t))

#if defined(__cplusplus) || defined(__OPENCL_VERSION__) || defined(SB_GLSL_CONSTANTS)
// The constants of span `span` (= i) of a degree-`degree` direction; `knots` is the whole knot
// vector. Entries past the degree are left as they were.
KL_FN void stair_constants(int span, int degree, SB_KNOTS_IN knots, SB_CONSTS_OUT c) {
  const int p = degree;
  for (int t = 0; t < 2 * p; ++t) SB_C_OUT(c, SB_KNOTS + t) = SB_KNOT_IN(knots, span - p + 1 + t);
  // x_{i-s} = knot p-1-s, x_{i+1+t} = knot p+t
  for (int s = 0; s < p; ++s)
    for (int t = 0; t < p; ++t)
      SB_C_OUT(c, SB_R + s * SB_MAX_DEG + t) =
          KL_CAST(SB_REAL, 1) / (SB_C_OUT(c, SB_KNOTS + p + t) - SB_C_OUT(c, SB_KNOTS + p - 1 - s));
  SB_C_OUT(c, SB_COLUMN) = KL_CAST(SB_REAL, 1);
  SB_C_OUT(c, SB_DIAGONAL) = KL_CAST(SB_REAL, 1);
  // h/(x_{i+l} - x_i) and h/(x_{i+1} - x_{i+1-l}), each in (0, 1]
  const SB_REAL h = SB_C_OUT(c, SB_KNOTS + p) - SB_C_OUT(c, SB_KNOTS + p - 1);
  for (int l = 1; l <= p; ++l) {
    SB_C_OUT(c, SB_COLUMN + l) = SB_C_OUT(c, SB_COLUMN + l - 1) * (h * SB_C_OUT(c, SB_R + l - 1));
    SB_C_OUT(c, SB_DIAGONAL + l) =
        SB_C_OUT(c, SB_DIAGONAL + l - 1) * (h * SB_C_OUT(c, SB_R + (l - 1) * SB_MAX_DEG));
  }
}
#endif

// basis[j] = N_{i-p+j,p}(u), j = 0..p (the order of A2.2). `knot_degree` is the degree the
// constants were built for: a lower degree reuses them -- r, A and B belong to the span alone,
// only the knot window moves (stair_derivative).
KL_FN void stair_basis(SB_CONSTS c, int degree, SB_REAL u,
                       KL_ARRAY_OUT(SB_REAL, basis, SB_MAX_ORDER), int knot_degree) {
  const int p = degree;
  const int o = knot_degree;  // x_{i-s} = knot o-1-s
  SB_REAL dl[SB_MAX_ORDER];   // u - x_{i-s}
  SB_REAL dr[SB_MAX_ORDER];   // x_{i+1+t} - u
  for (int s = 0; s < p; ++s) {
    dl[s] = u - SB_KNOT(c, o - 1 - s);
    dr[s] = SB_KNOT(c, o + s) - u;
  }
  // Column and diagonal functions by their closed forms: col[m] = N_{i,m}, diag[m] = N_{i-m,m}.
  SB_REAL col[SB_MAX_ORDER];
  SB_REAL diag[SB_MAX_ORDER];
  col[0] = KL_CAST(SB_REAL, 1);
  diag[0] = KL_CAST(SB_REAL, 1);
  SB_REAL pow_l = KL_CAST(SB_REAL, 1);  // ((u - x_i)/h)^m
  SB_REAL pow_r = KL_CAST(SB_REAL, 1);  // ((x_{i+1} - u)/h)^m
  const SB_REAL scaled_l = dl[0] * SB_RS(c, 0, 0);
  const SB_REAL scaled_r = dr[0] * SB_RS(c, 0, 0);
  for (int m = 1; m <= p; ++m) {
    pow_l *= scaled_l;
    pow_r *= scaled_r;
    col[m] = pow_l * SB_C(c, SB_COLUMN + m);
    diag[m] = pow_r * SB_C(c, SB_DIAGONAL + m);
  }
  basis[p] = col[p];   // k = 0: N_{i,p}
  basis[0] = diag[p];  // k = p: N_{i-p,p}
  for (int k = 1; k < p; ++k) {
    // Rectangle row r (r right steps taken), column l (l left steps): node N_{i-k+r, p-r-l}.
    // left step from (r, l):  dl[k-r] * r[k-r][p-k-l-1];  right step: dr[p-k-l] * r[k-r-1][p-k-l]
    const int w = p - k;
    SB_REAL t[SB_MAX_DEG];
    SB_REAL sum = KL_CAST(SB_REAL, 0);
    for (int r = 0; r < k; ++r) {
      for (int l = 0; l < w; ++l) {
        const SB_REAL from_above =
            r > 0 ? t[l] * (dr[w - l] * SB_RS(c, k - r, w - l)) : KL_CAST(SB_REAL, l == 0 ? 1 : 0);
        const SB_REAL from_left =
            l == 0 ? KL_CAST(SB_REAL, 0) : t[l - 1] * (dl[k - r] * SB_RS(c, k - r, w - l));
        t[l] = from_above + from_left;
      }
      // left step off the last column of the row lands on the diagonal N_{i-k+r, k-r}
      sum += t[w - 1] * (dl[k - r] * SB_RS(c, k - r, 0)) * diag[k - r];
    }
    // right step off the last row lands on the column N_{i, p-k-l}
    for (int l = 0; l < w; ++l) sum += t[l] * (dr[w - l] * SB_RS(c, 0, w - l)) * col[w - l];
    basis[p - k] = sum;
  }
}

// derivative[j] = d/du N_{i-p+j,p}(u), j = 0..p, by Piegl & Tiller eq. (2.7) on the degree p-1
// stair basis of the same span:
//   N'_{i-p+j,p} = p (N_{i-p+j,p-1} / (x_{i+j} - x_{i-p+j}) - N_{i-p+j+1,p-1} / (x_{i+j+1} -
//   x_{i-p+j+1}))
// where N_{i-p+j,p-1} is lower[j-1] (zero outside 0..p-1) and both denominators are per-span
// constants: 1 / (x_{i+j} - x_{i-p+j}) = r[p-j][j-1]. (vk-ksquad's normals.)
KL_FN void stair_derivative(SB_CONSTS c, int degree, SB_REAL u,
                            KL_ARRAY_OUT(SB_REAL, derivative, SB_MAX_ORDER)) {
  const int p = degree;
  SB_REAL lower[SB_MAX_ORDER];
  stair_basis(c, p - 1, u, lower, p);
  for (int j = 0; j <= p; ++j) {
    const SB_REAL left = j >= 1 ? lower[j - 1] * SB_RS(c, p - j, j - 1) : KL_CAST(SB_REAL, 0);
    const SB_REAL right = j <= p - 1 ? lower[j] * SB_RS(c, p - j - 1, j) : KL_CAST(SB_REAL, 0);
    derivative[j] = KL_CAST(SB_REAL, p) * (left - right);
  }
}
