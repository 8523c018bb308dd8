// The stair basis (003 §3.2) against the reference Cox-de Boor basis (reference/nurbs_math.h
// basis_functions): the C++ copy in long double, and the kernel's own output through the
// stair_basis_test kernel in f32 and f64, over degrees 1..9 and uniform, random, clustered and
// multiple-knot patterns. Also pins down where the paper's printed closed form holds (p <= 3).
#include "strategies/cl_stair/stair_basis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "strategies/cl_stair/cl_stair.h"

namespace nurbs {
namespace {

// Knot patterns with span `degree` as the tested one (2p+2 knots around it).
std::vector<std::vector<double>> knot_patterns(int p, std::mt19937_64& rng, int random) {
  std::vector<std::vector<double>> out;
  std::vector<double> uniform, clustered, multiple;
  for (int t = 0; t < 2 * p + 2; ++t) uniform.push_back(t);
  for (int t = 0; t < 2 * p + 2; ++t) clustered.push_back(t <= p ? t * 1e-4 : 1 + t);
  for (int t = 0; t < 2 * p + 2; ++t) multiple.push_back(t < p ? 0.0 : t - p);  // x_0..x_p = 0
  out = {uniform, clustered, multiple};
  std::uniform_real_distribution<double> d(0, 1);
  for (int r = 0; r < random; ++r) {
    std::vector<double> k;
    for (int t = 0; t < 2 * p + 2; ++t) k.push_back(d(rng));
    std::sort(k.begin(), k.end());
    out.push_back(k);
  }
  return out;
}

TEST(StairBasis, CppCopyEqualsReferenceBasisInLongDouble) {
  std::mt19937_64 rng(5);
  for (int p = 1; p <= kStairMaxDegree; ++p)
    for (const auto& kd : knot_patterns(p, rng, 20)) {
      const std::vector<long double> k(kd.begin(), kd.end());
      if (!(k[p] < k[p + 1])) continue;
      StairConstants<long double> c;
      stair_constants(p, p, k.data(), c);
      for (int s = 0; s <= 16; ++s) {
        const long double u = k[p] + (k[p + 1] - k[p]) * s / 16.0L;
        long double ref[kMaxOrder], st[kMaxOrder];
        basis_functions(p, u, p, k.data(), ref);
        stair_basis(c, p, u, st);
        for (int j = 0; j <= p; ++j) EXPECT_NEAR(double(st[j]), double(ref[j]), 1e-15) << p;
      }
    }
}

// The derivative from the degree p-1 stair basis (vk-ksquad's normals) against A2.3.
TEST(StairBasis, DerivativeEqualsReferenceInLongDouble) {
  std::mt19937_64 rng(7);
  for (int p = 1; p <= kStairMaxDegree; ++p)
    for (const auto& kd : knot_patterns(p, rng, 20)) {
      const std::vector<long double> k(kd.begin(), kd.end());
      if (!(k[p] < k[p + 1])) continue;
      StairConstants<long double> c;
      stair_constants(p, p, k.data(), c);
      for (int s = 0; s <= 16; ++s) {
        const long double u = k[p] + (k[p + 1] - k[p]) * s / 16.0L;
        long double ders[2][kMaxOrder], st[kMaxOrder];
        basis_function_derivatives(p, u, p, 1, k.data(), ders);
        stair_derivative(c, p, u, st);
        for (int j = 0; j <= p; ++j)
          EXPECT_NEAR(double(st[j]), double(ders[1][j]), 1e-13 * (1 + std::abs(double(ders[1][j]))))
              << "p=" << p << " j=" << j;
      }
    }
}

// The paper's printed closed form (first display of §3.2): one product per boundary term.
double printed(const std::vector<double>& x, int i, int k, int p, double u) {
  auto prod = [](auto f, int lo, int hi) {
    double r = 1;
    for (int l = lo; l <= hi; ++l) r *= f(l);
    return r;
  };
  auto col = [&](int c) {
    return std::pow(u - x[i], c) / prod([&](int l) { return x[i + l] - x[i]; }, 1, c);
  };
  auto dia = [&](int d) {
    return std::pow(x[i + 1] - u, d) / prod([&](int l) { return x[i + 1] - x[i - l + 1]; }, 1, d);
  };
  if (k == 0) return col(p);
  if (k == p) return dia(p);
  double s = 0;
  for (int j = 0; j < k; ++j)
    s += std::pow(u - x[i - k + j], p - k) * std::pow(x[i + k - 1 + j] - u, j) /
         prod([&](int l) { return x[i + l] - x[i - k + j]; }, 1, p - k + j) * dia(k - j);
  for (int j = 0; j < p - k; ++j) {
    const double e = x[i + p - k + 1 - j];
    s += std::pow(e - u, k) * std::pow(u - x[i - k], j) /
         prod([&](int l) { return e - x[i - l]; }, 0, k - 1 + j) * col(p - k - j);
  }
  return s;
}

TEST(StairBasis, PaperPrintedFormulaHoldsUpToDegree3Only) {
  const std::vector<double> x = {0, 0.1, 0.35, 0.4, 0.7, 0.75, 1.1, 1.3, 1.9, 2.0, 2.6, 3.0};
  for (int p = 1; p <= 4; ++p) {
    double worst = 0;
    const int i = p;
    const double u = x[i] + 0.37 * (x[i + 1] - x[i]);
    double ref[kMaxOrder];
    basis_functions(i, u, p, x.data(), ref);
    for (int k = 0; k <= p; ++k)
      worst = std::max(worst, std::fabs(printed(x, i, k, p, u) - ref[p - k]));
    if (p <= 3)
      EXPECT_LT(worst, 1e-14) << p;
    else
      EXPECT_GT(worst, 1e-3) << "the printed form is not an identity from degree 4";
  }
}

TEST(StairBasis, KernelEqualsReferenceBasis) {
  std::mt19937_64 rng(7);
  for (Precision precision : {Precision::f32, Precision::f64})
    for (int p = 1; p <= kStairMaxDegree; ++p)
      for (const auto& k : knot_patterns(p, rng, 2)) {  // each call builds the kernel
        if (!(k[p] < k[p + 1])) continue;
        std::vector<double> us;
        for (int s = 0; s <= 8; ++s) {
          const double u = k[p] + (k[p + 1] - k[p]) * s / 8.0;
          us.push_back(precision == Precision::f32 ? double(float(u)) : u);
        }
        // The kernel sees float-rounded knots in f32: compare with the reference on those.
        std::vector<long double> kr;
        for (double v : k) kr.push_back(precision == Precision::f32 ? float(v) : v);
        const auto got = stair_basis_on_device(p, p, k, us, precision);
        // Basis values are in [0,1] and sum to 1: absolute tolerance. f32: measured worst
        // ~1e-5 on the clustered pattern (relative spans 1e-4), f64: ~1e-12.
        const double tol = precision == Precision::f32 ? 5e-5 : 1e-11;
        for (std::size_t s = 0; s < us.size(); ++s) {
          if (!(us[s] >= double(kr[p]) && us[s] <= double(kr[p + 1]))) continue;
          long double ref[kMaxOrder];
          basis_functions(p, (long double)us[s], p, kr.data(), ref);
          for (int j = 0; j <= p; ++j)
            EXPECT_NEAR(got[s * (p + 1) + j], double(ref[j]), tol)
                << "p=" << p << " " << to_string(precision) << " s=" << s << " j=" << j;
        }
      }
}

}  // namespace
}  // namespace nurbs
