// cpu-tensor's kernels as each instruction set runs them. The strategy's own build is cloned for
// AVX-512, AVX2+FMA and baseline x86-64, and the loader picks one, so a test run on an AVX-512
// machine never executes the other two: this compiles them again, without clones, for baseline
// (isa_kernels_baseline.cpp) and AVX2 (isa_kernels_avx2.cpp), and checks every build against the
// scalar one (simd=off's) on rows whose runs start and end anywhere and whose output is
// misaligned, so the vector loops, their scalar tails and the xyz interleaving shuffles all run.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "strategies/cpu_tensor/tensor_kernels.h"

namespace nurbs::tensor {
namespace isa_baseline {
void evaluate_row(const RowJob<float>& job);
void evaluate_row(const RowJob<double>& job);
}  // namespace isa_baseline
namespace isa_avx2 {
void evaluate_row(const RowJob<float>& job);
void evaluate_row(const RowJob<double>& job);
}  // namespace isa_avx2
}  // namespace nurbs::tensor

namespace nurbs::tensor {
namespace {

// One row of `columns` samples in runs of the given lengths, degree 3, random positive weights
// and basis values, every output one value past an aligned start.
template <typename T>
struct Row {
  static constexpr int kDegree = 3;
  std::vector<T> curve, curve_du, basis, dbasis;
  std::vector<int> run_begin, run_first;
  int columns = 0;

  explicit Row(const std::vector<int>& runs, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> coordinate(-2, 2), weight(0.5, 2), value(0, 1);
    const int points = static_cast<int>(runs.size()) + kDegree;
    for (int i = 0; i < points; ++i) {
      for (int c = 0; c < 3; ++c) {
        curve.push_back(static_cast<T>(coordinate(rng)));
        curve_du.push_back(static_cast<T>(coordinate(rng)));
      }
      curve.push_back(static_cast<T>(weight(rng)));
      curve_du.push_back(static_cast<T>(0.1 * coordinate(rng)));
    }
    for (std::size_t r = 0; r < runs.size(); ++r) {
      run_begin.push_back(columns);
      run_first.push_back(static_cast<int>(r));
      columns += runs[r];
    }
    run_begin.push_back(columns);
    for (int k = 0; k < (kDegree + 1) * columns; ++k) {
      basis.push_back(static_cast<T>(value(rng)));
      dbasis.push_back(static_cast<T>(coordinate(rng)));
    }
  }

  struct Output {
    std::vector<T> positions, normals, unresolved;
  };

  template <typename Kernel>
  Output run(Kernel kernel, bool normals, bool rational) const {
    Output out;
    out.positions.assign(3 * columns + 1, T(-7));
    out.normals.assign(3 * columns + 1, T(-7));
    out.unresolved.assign(columns, T(-7));
    RowJob<T> job;
    job.curve = curve.data();
    job.curve_du = normals ? curve_du.data() : nullptr;
    job.run_begin = run_begin.data();
    job.run_first = run_first.data();
    job.runs = static_cast<int>(run_first.size());
    job.degree_v = kDegree;
    job.rational = rational;
    job.count_v_samples = columns;
    job.basis_v = basis.data();
    job.basis_dv = normals ? dbasis.data() : nullptr;
    job.positions = out.positions.data() + 1;
    job.normals = normals ? out.normals.data() + 1 : nullptr;
    job.unresolved = normals ? out.unresolved.data() : nullptr;
    kernel(job);
    return out;
  }
};

template <typename T>
void expect_same_values(const std::vector<T>& got, const std::vector<T>& want,
                        const std::string& what) {
  // FMA contraction differs between the builds: a few ulps of the values' scale.
  const double tolerance = (sizeof(T) == 4 ? 1e-5 : 1e-13);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i)
    ASSERT_NEAR(got[i], want[i], tolerance * (1 + std::fabs(want[i]))) << what << " at " << i;
}

template <typename T, typename Kernel>
void check_against_scalar(Kernel kernel, const std::string& name) {
  // Runs of every length around the vector widths (4, 8, 16), so each loop's entry, body and
  // tail are met.
  const std::vector<std::vector<int>> rows = {{1}, {3, 17}, {8, 8, 5}, {33, 2, 16, 31}, {64, 7}};
  unsigned seed = 1;
  for (const std::vector<int>& runs : rows) {
    const Row<T> row(runs, seed++);
    const auto scalar = [](const RowJob<T>& job) { no_simd::evaluate_row(job); };
    for (const bool normals : {false, true})
      for (const bool rational : {false, true}) {
        if (normals && !rational) continue;  // normals always take the rational path
        const auto got = row.run(kernel, normals, rational);
        const auto want = row.run(scalar, normals, rational);
        const std::string what = name +
                                 (normals    ? " normals"
                                  : rational ? " rational"
                                             : " plain") +
                                 " over " + std::to_string(row.columns) + " samples";
        expect_same_values(got.positions, want.positions, what + ", positions");
        if (!normals) continue;
        expect_same_values(got.normals, want.normals, what + ", normals");
        ASSERT_EQ(got.unresolved, want.unresolved) << what;
        // Resolved samples carry unit normals.
        for (int b = 0; b < row.columns; ++b) {
          const T* n = got.normals.data() + 1 + 3 * b;
          if (got.unresolved[b] != T(0)) continue;
          ASSERT_NEAR(std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), 1.0, 1e-5) << what;
        }
      }
  }
}

TEST(CpuTensorIsa, BaselineBuildAgreesWithTheScalarKernels) {
  check_against_scalar<float>([](const RowJob<float>& j) { isa_baseline::evaluate_row(j); },
                              "baseline f32");
  check_against_scalar<double>([](const RowJob<double>& j) { isa_baseline::evaluate_row(j); },
                               "baseline f64");
}

TEST(CpuTensorIsa, Avx2BuildAgreesWithTheScalarKernels) {
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma"))
    GTEST_SKIP() << "this CPU has no AVX2+FMA";
  check_against_scalar<float>([](const RowJob<float>& j) { isa_avx2::evaluate_row(j); },
                              "avx2 f32");
  check_against_scalar<double>([](const RowJob<double>& j) { isa_avx2::evaluate_row(j); },
                               "avx2 f64");
}

// The strategy's own build, whichever clone this machine's loader picked.
TEST(CpuTensorIsa, DispatchedBuildAgreesWithTheScalarKernels) {
  check_against_scalar<float>([](const RowJob<float>& j) { evaluate_row(j); }, "dispatched f32");
  check_against_scalar<double>([](const RowJob<double>& j) { evaluate_row(j); }, "dispatched f64");
}

}  // namespace
}  // namespace nurbs::tensor
