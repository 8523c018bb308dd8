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

// Positions and unit normals Su x Sv (A4.4 for the first derivatives) of the samples [b0, b1).
// The "resolved" test is the reference's (nurbs_math.h, detail::normalize_if_resolved); samples
// that fail it are flagged and finished by the caller with the reference's limit-normal code.
template <typename T, int Q>
NURBSBENCH_INLINE void run_normals(const RowJob<T>& job, int b0, int b1, const T* c, const T* cu) {
  T cx[Q + 1], cy[Q + 1], cz[Q + 1], cw[Q + 1];
  T ux[Q + 1], uy[Q + 1], uz[Q + 1], uw[Q + 1];
  for (int l = 0; l <= Q; ++l) {
    cx[l] = c[4 * l];
    cy[l] = c[4 * l + 1];
    cz[l] = c[4 * l + 2];
    cw[l] = c[4 * l + 3];
    ux[l] = cu[4 * l];
    uy[l] = cu[4 * l + 1];
    uz[l] = cu[4 * l + 2];
    uw[l] = cu[4 * l + 3];
  }
  const T* basis = job.basis_v;
  const T* dbasis = job.basis_dv;
  const int stride = job.count_v_samples;
  T* out = job.positions;
  T* nout = job.normals;
  unsigned char* unresolved = job.unresolved;
  const T threshold = T(1024) * std::numeric_limits<T>::epsilon();
  const T largest = std::numeric_limits<T>::max();
  for (int b = b0; b < b1; ++b) {
    T x = 0, y = 0, z = 0, w = 0, xu = 0, yu = 0, zu = 0, wu = 0, xv = 0, yv = 0, zv = 0, wv = 0;
    for (int l = 0; l <= Q; ++l) {
      const T n = basis[l * stride + b], d = dbasis[l * stride + b];
      x += n * cx[l];
      y += n * cy[l];
      z += n * cz[l];
      w += n * cw[l];
      xu += n * ux[l];
      yu += n * uy[l];
      zu += n * uz[l];
      wu += n * uw[l];
      xv += d * cx[l];
      yv += d * cy[l];
      zv += d * cz[l];
      wv += d * cw[l];
    }
    const T inv = T(1) / w;
    const T px = x * inv, py = y * inv, pz = z * inv;
    const T sux = (xu - wu * px) * inv, suy = (yu - wu * py) * inv, suz = (zu - wu * pz) * inv;
    const T svx = (xv - wv * px) * inv, svy = (yv - wv * py) * inv, svz = (zv - wv * pz) * inv;
    const T nx = suy * svz - suz * svy, ny = suz * svx - sux * svz, nz = sux * svy - suy * svx;
    const T length = std::sqrt(nx * nx + ny * ny + nz * nz);
    const T scale =
        std::sqrt(sux * sux + suy * suy + suz * suz) + std::sqrt(svx * svx + svy * svy + svz * svz);
    const bool resolved = length > threshold * scale * scale && length <= largest;
    const T il = T(1) / length;
    out[3 * b] = px;
    out[3 * b + 1] = py;
    out[3 * b + 2] = pz;
    nout[3 * b] = nx * il;
    nout[3 * b + 1] = ny * il;
    nout[3 * b + 2] = nz * il;
    unresolved[b] = resolved ? 0 : 1;
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
