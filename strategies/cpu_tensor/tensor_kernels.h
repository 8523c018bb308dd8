// The inner loops of cpu-tensor, kept apart from the strategy so they can be compiled for several
// instruction sets (GCC target_clones) and inspected with -fopt-info-vec
// (-DNURBSBENCH_VECTORIZE_REPORT=ON prints what the compiler vectorised in this folder).
#pragma once

#include <cstddef>

namespace nurbs::tensor {

// One row of the output grid (one u sample, every v sample) after the u contraction:
// `curve` holds the (p+1)-term u contraction of every control-point column, i.e. the homogeneous
// control points of the iso-curve at this u (count_v x 4, xyzw), `curve_du` the same with the
// u-derivative basis (only read when normals are requested).
template <typename T>
struct RowJob {
  const T* curve = nullptr;
  const T* curve_du = nullptr;
  // v samples grouped in runs of equal knot span: run r covers samples [run_begin[r],
  // run_begin[r+1]) and uses curve points run_first[r] .. run_first[r] + degree_v.
  const int* run_begin = nullptr;
  const int* run_first = nullptr;
  int runs = 0;
  int degree_v = 0;
  // false when every weight is 1: positions are then the plain sums, with no w to sum or divide by
  // (w would be the partition of unity, 1 up to rounding). Normals always take the rational path.
  bool rational = true;
  int count_v_samples = 0;      // stride of the basis tables
  const T* basis_v = nullptr;   // basis_v[l * count_v_samples + b]
  const T* basis_dv = nullptr;  // derivative table, same layout
  T* positions = nullptr;       // xyz per v sample
  T* normals = nullptr;         // xyz per v sample, or nullptr
  // Per v sample: 1 where the Su x Sv normal is noise. Of type T, not a byte: a narrower store
  // in the normal loop kept GCC from vectorising it.
  T* unresolved = nullptr;
};

// out[j * 4 + c] = sum_k basis[k] * net[(first + k) * count_v * 4 + j * 4 + c]: the u contraction
// of (p+1) control-point rows into one iso-curve.
void contract_rows(const float* net, int count_v, int first, int degree_u, const float* basis,
                   float* out);
void contract_rows(const double* net, int count_v, int first, int degree_u, const double* basis,
                   double* out);

// The v contraction, the divide by w and (optionally) the normal of one output row.
void evaluate_row(const RowJob<float>& job);
void evaluate_row(const RowJob<double>& job);

// The same kernels compiled without vectorisation (-fno-tree-vectorize -fno-tree-slp-vectorize, no
// clones): cpu-tensor's `simd=off`, so a run can tell what SIMD contributes.
namespace no_simd {
void contract_rows(const float* net, int count_v, int first, int degree_u, const float* basis,
                   float* out);
void contract_rows(const double* net, int count_v, int first, int degree_u, const double* basis,
                   double* out);
void evaluate_row(const RowJob<float>& job);
void evaluate_row(const RowJob<double>& job);
}  // namespace no_simd

}  // namespace nurbs::tensor
