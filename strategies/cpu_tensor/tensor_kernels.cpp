#include "strategies/cpu_tensor/tensor_kernels.h"

#include <cmath>
#include <limits>

// Each public kernel is compiled for AVX-512, AVX2+FMA and the baseline; the loader picks the best
// one the CPU has (GCC function multi-versioning), so the binary stays portable while using the
// widest vectors of the machine it runs on.
// Compiled a second time by tensor_kernels_no_simd.cpp, without vectorisation and without clones,
// into tensor::no_simd (cpu-tensor's simd=off option).
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && \
    !defined(NURBSBENCH_NO_TARGET_CLONES) && !defined(NURBSBENCH_TENSOR_NO_SIMD)
#define NURBSBENCH_SIMD_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define NURBSBENCH_SIMD_CLONES
#endif
#define NURBSBENCH_INLINE inline __attribute__((always_inline))

// NURBSBENCH_TENSOR_NAMESPACE: a test's build of the kernels for one instruction set, without
// clones (tests/strategies/cpu_tensor/isa_kernels_test.cpp), so the clones this machine's loader
// does not pick are checked too.
#if defined(NURBSBENCH_TENSOR_NAMESPACE)
namespace nurbs::tensor::NURBSBENCH_TENSOR_NAMESPACE {
#elif defined(NURBSBENCH_TENSOR_NO_SIMD)
namespace nurbs::tensor::no_simd {
#else
namespace nurbs::tensor {
#endif
namespace {

template <typename T>
NURBSBENCH_INLINE void contract_rows_impl(const T* net, int count_v, int first, int degree_u,
                                          const T* basis, T* out) {
  const std::size_t n = static_cast<std::size_t>(count_v) * 4;
  const T* row = net + static_cast<std::size_t>(first) * n;
  const T b0 = basis[0];
  for (std::size_t i = 0; i < n; ++i) out[i] = b0 * row[i];
  for (int k = 1; k <= degree_u; ++k) {
    const T bk = basis[k];
    const T* r = row + static_cast<std::size_t>(k) * n;
    for (std::size_t i = 0; i < n; ++i) out[i] += bk * r[i];
  }
}

// Positions of the samples [b0, b1) sharing one v span: Q+1 curve points held in registers, the
// sample loop vectorised (one lane per sample), basis rows read contiguously. Without weights the
// w sum and the divide go: on many-4096 at 64^2 they were a third of the kernel's work.
template <typename T, int Q, bool Rational>
NURBSBENCH_INLINE void run_positions(const RowJob<T>& job, int b0, int b1, const T* c) {
  T cx[Q + 1], cy[Q + 1], cz[Q + 1], cw[Q + 1];
  for (int l = 0; l <= Q; ++l) {
    cx[l] = c[4 * l];
    cy[l] = c[4 * l + 1];
    cz[l] = c[4 * l + 2];
    cw[l] = c[4 * l + 3];
  }
  const T* basis = job.basis_v;
  const int stride = job.count_v_samples;
  T* out = job.positions;
  for (int b = b0; b < b1; ++b) {
    T x = 0, y = 0, z = 0, w = 0;
    for (int l = 0; l <= Q; ++l) {
      const T n = basis[l * stride + b];
      x += n * cx[l];
      y += n * cy[l];
      z += n * cz[l];
      if constexpr (Rational) w += n * cw[l];
    }
    if constexpr (Rational) {
      const T inv = T(1) / w;
      x *= inv;
      y *= inv;
      z *= inv;
    }
    out[3 * b] = x;
    out[3 * b + 1] = y;
    out[3 * b + 2] = z;
  }
}

// 32-byte GCC vectors (8 floats, 4 doubles): one AVX2 register, half an AVX-512 one; the baseline
// clone splits each into two SSE registers. Not 64 bytes: twelve accumulators of two registers
// each would not fit AVX2's sixteen, and on the AVX-512 clone 64-byte vectors were no faster
// (patch144 4096^2 normals, one run on the 2-core EPYC guest: f32 34 ms against 24-30, f64 53
// against 58-65 ms, the store pass moving by as much between processes).
template <typename T>
struct LanesOf;
template <>
struct LanesOf<float> {
  typedef float type __attribute__((vector_size(32)));
  typedef int mask __attribute__((vector_size(32)));
};
template <>
struct LanesOf<double> {
  typedef double type __attribute__((vector_size(32)));
  typedef long long mask __attribute__((vector_size(32)));
};
template <typename T>
using Lanes = typename LanesOf<T>::type;
template <typename T>
using LaneIndex = typename LanesOf<T>::mask;
template <typename T>
inline constexpr int kLanes = static_cast<int>(32 / sizeof(T));

// The no_simd build (simd=off) takes the scalar path for every sample: explicit vectors there
// would put SIMD back into the baseline it exists to measure against.
#ifdef NURBSBENCH_TENSOR_NO_SIMD
inline constexpr bool kExplicitVectors = false;
#else
inline constexpr bool kExplicitVectors = true;
#endif

// Helpers on vectors take and give them by reference: a vector passed or returned by value in a
// function built without AVX is an ABI change GCC warns of (-Wpsabi), inlined or not.
template <typename T>
NURBSBENCH_INLINE void sqrt_into(const T& v, T& r) {
  r = std::sqrt(v);
}
// Lane by lane; GCC turns the loop into one vector square root (-fno-math-errno).
template <typename T>
NURBSBENCH_INLINE void sqrt_into(const Lanes<T>& v, Lanes<T>& r) {
  for (int k = 0; k < kLanes<T>; ++k) r[k] = std::sqrt(v[k]);
}

// Writes kLanes samples' x, y and z as 3 kLanes interleaved values (the result's xyz layout):
// two two-vector shuffles for each output vector (vpermt2ps/pd on AVX-512), no trip through
// memory. The zeros in the first shuffles are lanes the second one replaces.
NURBSBENCH_INLINE void store_xyz(float* out, const Lanes<float>& x, const Lanes<float>& y,
                                 const Lanes<float>& z) {
  using I = LaneIndex<float>;
  const Lanes<float> t0 = __builtin_shuffle(x, y, I{0, 8, 0, 1, 9, 0, 2, 10});
  const Lanes<float> t1 = __builtin_shuffle(x, y, I{0, 3, 11, 0, 4, 12, 0, 5});
  const Lanes<float> t2 = __builtin_shuffle(x, y, I{13, 0, 6, 14, 0, 7, 15, 0});
  const Lanes<float> o0 = __builtin_shuffle(t0, z, I{0, 1, 8, 3, 4, 9, 6, 7});
  const Lanes<float> o1 = __builtin_shuffle(t1, z, I{10, 1, 2, 11, 4, 5, 12, 7});
  const Lanes<float> o2 = __builtin_shuffle(t2, z, I{0, 13, 2, 3, 14, 5, 6, 15});
  __builtin_memcpy(out, &o0, sizeof o0);
  __builtin_memcpy(out + 8, &o1, sizeof o1);
  __builtin_memcpy(out + 16, &o2, sizeof o2);
}
NURBSBENCH_INLINE void store_xyz(double* out, const Lanes<double>& x, const Lanes<double>& y,
                                 const Lanes<double>& z) {
  using I = LaneIndex<double>;
  const Lanes<double> t0 = __builtin_shuffle(x, y, I{0, 4, 0, 1});
  const Lanes<double> t1 = __builtin_shuffle(x, y, I{5, 0, 2, 6});
  const Lanes<double> t2 = __builtin_shuffle(x, y, I{0, 3, 7, 0});
  const Lanes<double> o0 = __builtin_shuffle(t0, z, I{0, 1, 4, 3});
  const Lanes<double> o1 = __builtin_shuffle(t1, z, I{0, 5, 2, 3});
  const Lanes<double> o2 = __builtin_shuffle(t2, z, I{6, 1, 2, 7});
  __builtin_memcpy(out, &o0, sizeof o0);
  __builtin_memcpy(out + 4, &o1, sizeof o1);
  __builtin_memcpy(out + 8, &o2, sizeof o2);
}
template <typename T>
NURBSBENCH_INLINE void store_xyz(T* out, const T& x, const T& y, const T& z) {
  out[0] = x;
  out[1] = y;
  out[2] = z;
}

// The homogeneous sums of one sample or of kLanes samples (V = T or Lanes<T>): S = (x, y, z, w)
// and its u and v derivatives.
template <typename V>
struct HomogeneousSums {
  V x, y, z, w, xu, yu, zu, wu, xv, yv, zv, wv;
};

// Position, unit normal and unresolved flag from the sums, written at sample `at`. The normal is
// (Su x Sv) with each tangent left multiplied by w (Su w = Su_h - w_u P): the factor w^2 scales
// the cross product, its length and the tangents' squared lengths alike, so neither the direction
// nor the resolved test changes, and two vector multiplies by 1/w go. The test is a slightly
// stricter form of the reference's (nurbs_math.h, detail::normalize_if_resolved): the reference's
// bound is threshold (|Su| + |Sv|)^2; 2 (|Su|^2 + |Sv|^2) is never below it, so with it (and 1/16
// more for rounding) a sample resolved here is resolved there too, and one near the edge of the
// rule is flagged and takes the reference's own code (the caller's). It needs no square root of
// the tangents.
template <typename T, typename V>
NURBSBENCH_INLINE void finish_normal(const HomogeneousSums<V>& s, T* positions, T* normals,
                                     T* unresolved, std::size_t at) {
  const T threshold = T(1024) * std::numeric_limits<T>::epsilon() * T(2.125);
  const T largest = std::numeric_limits<T>::max();
  const V inv = T(1) / s.w;
  const V px = s.x * inv, py = s.y * inv, pz = s.z * inv;
  const V sux = s.xu - s.wu * px, suy = s.yu - s.wu * py, suz = s.zu - s.wu * pz;
  const V svx = s.xv - s.wv * px, svy = s.yv - s.wv * py, svz = s.zv - s.wv * pz;
  const V nx = suy * svz - suz * svy, ny = suz * svx - sux * svz, nz = sux * svy - suy * svx;
  V length;
  sqrt_into<T>(nx * nx + ny * ny + nz * nz, length);
  const V tangents2 = (sux * sux + suy * suy + suz * suz) + (svx * svx + svy * svy + svz * svz);
  // & rather than &&: no branch, and lane by lane for vectors. NaN fails both.
  const auto resolved = (length > threshold * tangents2) & (length <= largest);
  const V il = T(1) / length;
  store_xyz(positions + 3 * at, px, py, pz);
  store_xyz(normals + 3 * at, nx * il, ny * il, nz * il);
  const V zero{}, one = zero + T(1);
  const V flag = resolved ? zero : one;  // lane by lane for vectors
  __builtin_memcpy(unresolved + at, &flag, sizeof flag);
}

// The sums of the samples from b (kLanes of them with V = Lanes<T>, one with V = T) and their
// finish: the position and both derivative contractions fused, each basis row read once.
template <typename T, typename V, int Q>
NURBSBENCH_INLINE void normal_samples(const RowJob<T>& job, int b, const T* c, const T* cu) {
  const std::size_t stride = static_cast<std::size_t>(job.count_v_samples);
  HomogeneousSums<V> s{};
  for (int l = 0; l <= Q; ++l) {
    const std::size_t row = static_cast<std::size_t>(l) * stride + static_cast<std::size_t>(b);
    V n, d;  // unaligned loads (memcpy, not a vector-returning helper: -Wpsabi)
    __builtin_memcpy(&n, job.basis_v + row, sizeof n);
    __builtin_memcpy(&d, job.basis_dv + row, sizeof d);
    s.x += n * c[4 * l];
    s.y += n * c[4 * l + 1];
    s.z += n * c[4 * l + 2];
    s.w += n * c[4 * l + 3];
    s.xu += n * cu[4 * l];
    s.yu += n * cu[4 * l + 1];
    s.zu += n * cu[4 * l + 2];
    s.wu += n * cu[4 * l + 3];
    s.xv += d * c[4 * l];
    s.yv += d * c[4 * l + 1];
    s.zv += d * c[4 * l + 2];
    s.wv += d * c[4 * l + 3];
  }
  finish_normal<T, V>(s, job.positions, job.normals, job.unresolved, b);
}

// Positions and unit normals Su x Sv (A4.4 for the first derivatives) of the samples [b0, b1),
// kLanes at a time, everything in registers: the twelve sums, then the divide by w, the cross
// product, the normalisation and the interleaved stores. Written so because the one-loop scalar
// form was not vectorised by GCC 12 (-fopt-info-vec: control flow from sqrt's errno, mixed
// char/float stores), which made normals 9-17x slower than positions (issue 30), and because the
// two-sweep form before this one (sums of a block of 32 stored to arrays, then a finishing loop
// the auto-vectoriser widened to 64 bytes) stalled on store forwarding: its 64-byte loads of the
// 32-byte stores just made were its hottest instruction (perf annotate). Samples that fail the
// resolved test are flagged (1 in job.unresolved) and finished by the caller with the reference's
// limit-normal code, off this loop.
template <typename T, int Q>
NURBSBENCH_INLINE void run_normals(const RowJob<T>& job, int b0, int b1, const T* c, const T* cu) {
  int b = b0;
  for (; kExplicitVectors && b + kLanes<T> <= b1; b += kLanes<T>)
    normal_samples<T, Lanes<T>, Q>(job, b, c, cu);
  for (; b < b1; ++b) normal_samples<T, T, Q>(job, b, c, cu);  // the run's last, under a vector
}

template <typename T, int Q>
NURBSBENCH_INLINE void row_for_degree(const RowJob<T>& job) {
  for (int r = 0; r < job.runs; ++r) {
    const int b0 = job.run_begin[r], b1 = job.run_begin[r + 1];
    const T* c = job.curve + 4 * job.run_first[r];
    if (job.normals)
      run_normals<T, Q>(job, b0, b1, c, job.curve_du + 4 * job.run_first[r]);
    else if (job.rational)
      run_positions<T, Q, true>(job, b0, b1, c);
    else
      run_positions<T, Q, false>(job, b0, b1, c);
  }
}

// The v degree as a compile-time constant, so the (q+1)-term sums are unrolled and the sample
// loop is the vectorised one.
template <typename T>
NURBSBENCH_INLINE void evaluate_row_impl(const RowJob<T>& job) {
  switch (job.degree_v) {
#define NURBSBENCH_DEGREE_CASE(q) \
  case q:                         \
    return row_for_degree<T, q>(job);
    NURBSBENCH_DEGREE_CASE(1)
    NURBSBENCH_DEGREE_CASE(2)
    NURBSBENCH_DEGREE_CASE(3)
    NURBSBENCH_DEGREE_CASE(4)
    NURBSBENCH_DEGREE_CASE(5)
    NURBSBENCH_DEGREE_CASE(6)
    NURBSBENCH_DEGREE_CASE(7)
    NURBSBENCH_DEGREE_CASE(8)
    NURBSBENCH_DEGREE_CASE(9)
    NURBSBENCH_DEGREE_CASE(10)
    NURBSBENCH_DEGREE_CASE(11)
    NURBSBENCH_DEGREE_CASE(12)
    NURBSBENCH_DEGREE_CASE(13)
    NURBSBENCH_DEGREE_CASE(14)
    NURBSBENCH_DEGREE_CASE(15)
#undef NURBSBENCH_DEGREE_CASE
    default:
      break;
  }
}

}  // namespace

NURBSBENCH_SIMD_CLONES void contract_rows(const float* net, int count_v, int first, int degree_u,
                                          const float* basis, float* out) {
  contract_rows_impl(net, count_v, first, degree_u, basis, out);
}
NURBSBENCH_SIMD_CLONES void contract_rows(const double* net, int count_v, int first, int degree_u,
                                          const double* basis, double* out) {
  contract_rows_impl(net, count_v, first, degree_u, basis, out);
}
NURBSBENCH_SIMD_CLONES void evaluate_row(const RowJob<float>& job) {
  evaluate_row_impl(job);
}
NURBSBENCH_SIMD_CLONES void evaluate_row(const RowJob<double>& job) {
  evaluate_row_impl(job);
}

}  // namespace nurbs::tensor (or nurbs::tensor::no_simd, or a test's namespace)
