// Direct trimming, the device half (Schollmeyer & Fröhlich 2009, "Direct trimming of NURBS
// surfaces on the GPU", §4-5): classify a (u, v) against a surface's trim loops by walking the
// row of the two-level acceleration structure that holds v, and bisecting the exact rational
// Bézier pieces that may cross the ray from (u, v) towards +u. Written ONCE in a C subset and
// compiled as C++ (strategies/trim_direct/trim_tables.cpp: the tested C++ path), OpenCL C
// (cl-stair's classify kernel) and GLSL (strategies/vulkan/trim_classify.comp, vk-ksquad's
// fragment stage); the few differences are the macros below. No include guard in C++: the C++
// wrapper includes it once per scalar type (float as the devices run it, double).
//
// The tables (built on the host by trim_tables.cpp, see TrimTables there):
//   ints  [base]       row count R (0: no loops crossing any row -- every sample is outside)
//   ints  [base + 1]   index in `reals` of the R + 1 row breaks b_0 < ... < b_R (the sorted
//                      distinct v of the pieces' ends)
//   ints  [base + 2 + k], k = 0..R   index in `ints` of row k's first entry (row k: its entries up
//                      to row k + 1's first); an entry is two ints: the piece's index in `reals`
//                      and its degree. A row lists the pieces spanning it, sorted by their u-min.
//   reals [piece]      u-min, u-max of the piece, then (u, v, w) of its degree + 1 control points
//                      (Cartesian points and weights: the ends are exactly the stored points, so
//                      the row breaks and the pieces' ends compare exactly)
// Every piece is monotone in u and in v (split at the extrema on the host), so the sub-curve of
// any parameter interval lies in the box of its two end points: the paper's bisection test.
//
// Counting rule (reference/trim_crossings.h's, made local to a piece): a point of a loop is
// "above" the row when its v >= the sample's v; the sample is inside when an odd number of
// above/below changes lie at u' > u. A piece monotone in v changes state exactly once when
// v_min < v <= v_max (half-open), never otherwise -- so a vertex on the row counts once where
// the loop passes through it and twice (no change) where it touches, exactly, without any
// special case. A row k holds the samples with b_k < v <= b_{k+1}: the pieces that span it are
// exactly those whose half-open v-range contains every such v.

#if defined(__cplusplus) || defined(GL_GOOGLE_include_directive)
#include "../kernel_language/kernel_language.h"
#endif
#if !defined(KL_GLSL)
// C++: the includer defines TD_REAL (float or double). OpenCL: the build options define TD_REAL
// (and enable cl_khr_fp64 for double).
#define TD_REALS_PARAM KL_GLOBAL const TD_REAL *td_reals,
#define TD_BUFFER_PARAMS KL_GLOBAL const TD_REAL *td_reals, KL_GLOBAL const int *td_ints,
#define TD_REALS_ARG td_reals,
#else
// GLSL: the includer declares the storage buffers `td_reals` (float) and `td_ints` (int); a
// function cannot take a buffer as a parameter, so the buffers are globals here.
#define TD_REAL float
#define TD_REALS_PARAM
#define TD_BUFFER_PARAMS
#define TD_REALS_ARG
#endif

// The largest piece order (reference/validation.h kMaxDegree + 1).
#define TD_MAX_ORDER 16

// 1 when the crossing of the row v by the piece at `piece` (a piece spanning the row) lies at
// u' > u, by bisection of the exact curve (the paper's Algorithm 1): the sub-curve between two
// parameters lies in the box of its ends, so a box wholly right (left) of u decides the answer;
// otherwise halve and keep the half whose v-range holds v. Stops when the box is narrower than
// `epsilon` in u or after `iterations` halvings and then decides by the box's middle: exact
// except for samples within epsilon (plus the scalar's rounding) of the curve. The control points
// are read once into registers; the halvings read no buffer.
KL_FN int td_piece_crosses_right(TD_REALS_PARAM int piece, int degree, TD_REAL u, TD_REAL v,
                                 TD_REAL epsilon, int iterations) {
  TD_REAL hu[TD_MAX_ORDER];
  TD_REAL hv[TD_MAX_ORDER];
  TD_REAL hw[TD_MAX_ORDER];
  TD_REAL wu[TD_MAX_ORDER];
  TD_REAL wv[TD_MAX_ORDER];
  TD_REAL ww[TD_MAX_ORDER];
  for (int i = 0; i <= degree; ++i) {
    const TD_REAL w = td_reals[piece + 2 + 3 * i + 2];
    hu[i] = td_reals[piece + 2 + 3 * i] * w;
    hv[i] = td_reals[piece + 2 + 3 * i + 1] * w;
    hw[i] = w;
  }
  TD_REAL t0 = KL_CAST(TD_REAL, 0);
  TD_REAL t1 = KL_CAST(TD_REAL, 1);
  TD_REAL u0 = td_reals[piece + 2];
  TD_REAL v0 = td_reals[piece + 3];
  TD_REAL u1 = td_reals[piece + 2 + 3 * degree];
  TD_REAL v1 = td_reals[piece + 3 + 3 * degree];
  const int rising = v1 > v0 ? 1 : 0;
  for (int iteration = 0; iteration <= iterations; ++iteration) {
    const TD_REAL lo = u0 < u1 ? u0 : u1;
    const TD_REAL hi = u0 < u1 ? u1 : u0;
    if (u < lo) return 1;
    if (u >= hi) return 0;
    if (hi - lo <= epsilon || iteration == iterations) break;
    const TD_REAL tm = (t0 + t1) * KL_CAST(TD_REAL, 0.5);
    if (!(tm > t0 && tm < t1)) break;
    // de Casteljau in homogeneous (w·u, w·v, w) at tm.
    for (int i = 0; i <= degree; ++i) {
      wu[i] = hu[i];
      wv[i] = hv[i];
      ww[i] = hw[i];
    }
    for (int r = 1; r <= degree; ++r)
      for (int i = 0; i <= degree - r; ++i) {
        wu[i] = (KL_CAST(TD_REAL, 1) - tm) * wu[i] + tm * wu[i + 1];
        wv[i] = (KL_CAST(TD_REAL, 1) - tm) * wv[i] + tm * wv[i + 1];
        ww[i] = (KL_CAST(TD_REAL, 1) - tm) * ww[i] + tm * ww[i + 1];
      }
    const TD_REAL um = wu[0] / ww[0];
    const TD_REAL vm = wv[0] / ww[0];
    // Rising: the state turns "above" at the first t with v(t) >= v; falling: "below" at the
    // first t with v(t) < v. The change lies in [t0, tm] when the state at tm is already the new
    // one.
    const int changed = rising == 1 ? (vm >= v ? 1 : 0) : (vm < v ? 1 : 0);
    if (changed == 1) {
      t1 = tm;
      u1 = um;
      v1 = vm;
    } else {
      t0 = tm;
      u0 = um;
      v0 = vm;
    }
  }
  return u < (u0 + u1) * KL_CAST(TD_REAL, 0.5) ? 1 : 0;
}

// Classifies (u, v) against the trim whose tables start at ints[base]: returns
// 2 * (buffer elements read) + (1 when inside, by the even-odd rule). The read count is the cost
// counter (gpucast's cost view counts the same kind of fetches). One packed int because GLSL and
// OpenCL C share no way to return two values.
KL_FN int td_classify(TD_BUFFER_PARAMS int base, TD_REAL u, TD_REAL v, TD_REAL epsilon,
                      int iterations) {
  const int rows = td_ints[base];
  int reads = 1;
  if (rows == 0) return 2 * reads;
  const int breaks = td_ints[base + 1];
  reads += 3;
  if (!(v > td_reals[breaks] && v <= td_reals[breaks + rows])) return 2 * reads;
  // Level one: the row with b_lo < v <= b_hi, by binary search over the breaks.
  int lo = 0;
  int hi = rows;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    ++reads;
    if (td_reals[breaks + mid] < v)
      lo = mid;
    else
      hi = mid;
  }
  const int first = td_ints[base + 2 + lo];
  const int last = td_ints[base + 3 + lo];
  reads += 2;
  // Level two: the row's pieces by increasing u-min. Once a u-min is right of u, that piece and
  // every later one cross right of u: counted without reading them.
  int parity = 0;
  for (int entry = first; entry < last; entry += 2) {
    const int piece = td_ints[entry];
    const int degree = td_ints[entry + 1];
    reads += 3;
    if (td_reals[piece] > u) {
      parity += (last - entry) / 2;
      break;
    }
    ++reads;
    if (td_reals[piece + 1] <= u) continue;  // wholly left: its crossing is not right of u
    reads += 3 * (degree + 1);
    parity += td_piece_crosses_right(TD_REALS_ARG piece, degree, u, v, epsilon, iterations);
  }
  return 2 * reads + parity % 2;
}

#if defined(__cplusplus)
#undef TD_REALS_PARAM
#undef TD_BUFFER_PARAMS
#undef TD_REALS_ARG
#undef TD_MAX_ORDER
#endif
