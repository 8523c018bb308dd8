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

#ifdef NURBSBENCH_TENSOR_NO_SIMD
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

// Samples per block of the normal kernel: the twelve sums of a block are kept in arrays of this
// length (1.5 KiB of floats, 3 KiB of doubles: L1), then finished in one sweep.
inline constexpr int kNormalBlock = 32;

// 32-byte GCC vectors (8 floats, 4 doubles): one AVX2 register, half an AVX-512 one (on Zen 4 the
// AVX-512 units are 256 bits wide anyway); the baseline clone splits each into two SSE registers.
template <typename T>
struct LanesOf;
template <>
struct LanesOf<float> {
  typedef float type __attribute__((vector_size(32)));
};
template <>
struct LanesOf<double> {
  typedef double type __attribute__((vector_size(32)));
};
template <typename T>
using Lanes = typename LanesOf<T>::type;
template <typename T>
inline constexpr int kLanes = static_cast<int>(32 / sizeof(T));

// The no_simd build (simd=off) takes the scalar path for every sample: explicit vectors there
// would put SIMD back into the baseline it exists to measure against.
#ifdef NURBSBENCH_TENSOR_NO_SIMD
inline constexpr bool kExplicitVectors = false;
#else
inline constexpr bool kExplicitVectors = true;
#endif

// Positions and unit normals Su x Sv (A4.4 for the first derivatives) of the samples [b0, b1),
// in blocks of kNormalBlock: first the sums S (xyzw), Su and Sv of every sample of the block, the
// position and both derivative contractions fused (each basis row read once, the twelve
// accumulators of kLanes samples held in registers over the q+1 terms), then one sweep divides by
// w, crosses and normalises. Written so because the one-loop form (each sum a scalar, the l loop
// inside the sample loop) was not vectorised by GCC 12 (-fopt-info-vec: control flow from sqrt's
// errno, mixed char/float stores), which made normals 9-17x slower than positions (issue 30), and
// an auto-vectorised accumulation over arrays stored all twelve sums at every term. The
// "resolved" test is a slightly stricter form of the reference's (nurbs_math.h,
// detail::normalize_if_resolved); samples that fail it are flagged (1 in job.unresolved) and
// finished by the caller with the reference's limit-normal code, off this loop.
template <typename T, int Q>
NURBSBENCH_INLINE void run_normals(const RowJob<T>& job, int b0, int b1, const T* c, const T* cu) {
  constexpr int W = kLanes<T>;
  const T* __restrict basis = job.basis_v;
  const T* __restrict dbasis = job.basis_dv;
  const int stride = job.count_v_samples;
  T* __restrict out = job.positions;
  T* __restrict nout = job.normals;
  T* __restrict unresolved = job.unresolved;
  const T threshold = T(1024) * std::numeric_limits<T>::epsilon();
  const T largest = std::numeric_limits<T>::max();
  for (int start = b0; start < b1; start += kNormalBlock) {
    const int m = b1 - start < kNormalBlock ? b1 - start : kNormalBlock;
    alignas(64) T x[kNormalBlock], y[kNormalBlock], z[kNormalBlock], w[kNormalBlock];
    alignas(64) T xu[kNormalBlock], yu[kNormalBlock], zu[kNormalBlock], wu[kNormalBlock];
    alignas(64) T xv[kNormalBlock], yv[kNormalBlock], zv[kNormalBlock], wv[kNormalBlock];
    int i = 0;
    for (; kExplicitVectors && i + W <= m; i += W) {
      Lanes<T> ax{}, ay{}, az{}, aw{}, aux{}, auy{}, auz{}, auw{}, avx{}, avy{}, avz{}, avw{};
      for (int l = 0; l <= Q; ++l) {
        const std::size_t row = static_cast<std::size_t>(l) * stride + start + i;
        Lanes<T> n, d;  // unaligned loads (memcpy, not a vector-returning helper: -Wpsabi)
        __builtin_memcpy(&n, basis + row, sizeof n);
        __builtin_memcpy(&d, dbasis + row, sizeof d);
        ax += n * c[4 * l];
        ay += n * c[4 * l + 1];
        az += n * c[4 * l + 2];
        aw += n * c[4 * l + 3];
        aux += n * cu[4 * l];
        auy += n * cu[4 * l + 1];
        auz += n * cu[4 * l + 2];
        auw += n * cu[4 * l + 3];
        avx += d * c[4 * l];
        avy += d * c[4 * l + 1];
        avz += d * c[4 * l + 2];
        avw += d * c[4 * l + 3];
      }
      __builtin_memcpy(x + i, &ax, sizeof ax);
      __builtin_memcpy(y + i, &ay, sizeof ay);
      __builtin_memcpy(z + i, &az, sizeof az);
      __builtin_memcpy(w + i, &aw, sizeof aw);
      __builtin_memcpy(xu + i, &aux, sizeof aux);
      __builtin_memcpy(yu + i, &auy, sizeof auy);
      __builtin_memcpy(zu + i, &auz, sizeof auz);
      __builtin_memcpy(wu + i, &auw, sizeof auw);
      __builtin_memcpy(xv + i, &avx, sizeof avx);
      __builtin_memcpy(yv + i, &avy, sizeof avy);
      __builtin_memcpy(zv + i, &avz, sizeof avz);
      __builtin_memcpy(wv + i, &avw, sizeof avw);
    }
    for (; i < m; ++i) {  // the run's last samples, fewer than a vector
      T s[12] = {};
      for (int l = 0; l <= Q; ++l) {
        const std::size_t row = static_cast<std::size_t>(l) * stride + start + i;
        const T n = basis[row], d = dbasis[row];
        for (int k = 0; k < 4; ++k) {
          s[k] += n * c[4 * l + k];
          s[4 + k] += n * cu[4 * l + k];
          s[8 + k] += d * c[4 * l + k];
        }
      }
      x[i] = s[0], y[i] = s[1], z[i] = s[2], w[i] = s[3];
      xu[i] = s[4], yu[i] = s[5], zu[i] = s[6], wu[i] = s[7];
      xv[i] = s[8], yv[i] = s[9], zv[i] = s[10], wv[i] = s[11];
    }
    T* __restrict p = out + 3 * static_cast<std::size_t>(start);
    T* __restrict q = nout + 3 * static_cast<std::size_t>(start);
    T* __restrict flag = unresolved + start;
    for (int i = 0; i < m; ++i) {
      const T inv = T(1) / w[i];
      const T px = x[i] * inv, py = y[i] * inv, pz = z[i] * inv;
      const T sux = (xu[i] - wu[i] * px) * inv, suy = (yu[i] - wu[i] * py) * inv,
              suz = (zu[i] - wu[i] * pz) * inv;
      const T svx = (xv[i] - wv[i] * px) * inv, svy = (yv[i] - wv[i] * py) * inv,
              svz = (zv[i] - wv[i] * pz) * inv;
      const T nx = suy * svz - suz * svy, ny = suz * svx - sux * svz, nz = sux * svy - suy * svx;
      // sqrt needs -fno-math-errno (CMakeLists.txt) to stay a vector instruction.
      const T length = std::sqrt(nx * nx + ny * ny + nz * nz);
      // The reference's bound is threshold (|Su| + |Sv|)^2; 2 (|Su|^2 + |Sv|^2) is never below
      // (|Su| + |Sv|)^2, so with it (and 1/16 more for rounding) a sample resolved here is resolved
      // there too, and one near the edge of the rule is flagged and takes the reference's own code.
      // It saves two square roots a sample: in a loop of this kernel alone, writing a row-sized
      // buffer (no memory traffic), f32 normals at 4096^2 went from 31-36 ms to 27 ms (issue 30).
      const T tangents2 = (sux * sux + suy * suy + suz * suz) + (svx * svx + svy * svy + svz * svz);
      // & rather than &&: no branch in the loop.
      const bool resolved = (length > threshold * T(2.125) * tangents2) & (length <= largest);
      const T il = T(1) / length;
      p[3 * i] = px;
      p[3 * i + 1] = py;
      p[3 * i + 2] = pz;
      q[3 * i] = nx * il;
      q[3 * i + 1] = ny * il;
      q[3 * i + 2] = nz * il;
      flag[i] = resolved ? T(0) : T(1);
    }
  }
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

}  // namespace nurbs::tensor (or nurbs::tensor::no_simd)
