// The single-source basis pass of vk-compute (strategies/vk_compute/tensor_basis.h) in its two
// builds on the same inputs -- C++ (float, double) and GLSL (the strategy's basis shader on the
// Vulkan device, lavapipe here: f32, and f64 where the device has shaderFloat64) -- against the
// reference (reference/nurbs_math.h A2.1 and A2.3 in long double, on the knots and parameters as
// each build sees them after rounding) and against each other. Degrees 1..15; uniform, clustered,
// repeated interior and random knots; 9 parameters per span (both ends), the domain ends and
// parameters just outside the domain.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "reference/nurbs_math.h"
#include "strategies/registry.h"
#include "strategies/vk_compute/tensor_basis.h"
#include "strategies/vk_compute/vk_compute.h"

namespace nurbs {
namespace {

struct Case {
  int degree = 1;
  std::string pattern;
  std::vector<double> knots;
  std::vector<double> u;
};

std::vector<double> clamped(int p, const std::vector<double>& interior) {
  std::vector<double> k(p + 1, 0.0);
  k.insert(k.end(), interior.begin(), interior.end());
  k.insert(k.end(), p + 1, 1.0);
  return k;
}

std::vector<Case> cases() {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Case> out;
  for (int p = 1; p <= TB_MAX_DEG; ++p) {
    std::vector<double> uniform, clustered, repeated, random;
    for (int k = 1; k <= 4; ++k) uniform.push_back(k / 5.0);
    // geometric toward 0: spans down to 1e-4 of the domain
    for (int k = 4; k >= 1; --k) clustered.push_back(std::pow(10.0, -k));
    for (int k = 0; k < std::min(p, 3); ++k) repeated.push_back(0.5);
    repeated.insert(repeated.begin(), 0.25);
    for (int k = 0; k < 5; ++k) random.push_back(unit(rng));
    std::sort(random.begin(), random.end());
    for (auto [name, interior] : {std::pair{"uniform", uniform}, std::pair{"clustered", clustered},
                                  std::pair{"repeated", repeated}, std::pair{"random", random}}) {
      Case c{p, name, clamped(p, interior), {}};
      for (std::size_t s = p; s + 1 < c.knots.size() - p; ++s) {
        const double a = c.knots[s], b = c.knots[s + 1];
        if (!(a < b)) continue;
        for (int t = 0; t <= 8; ++t) c.u.push_back(a + (b - a) * t / 8.0);
      }
      // just outside the domain (a float-rounded end): the first / last span, extrapolated
      c.u.push_back(-1e-7);
      c.u.push_back(1.0 + 1e-7);
      out.push_back(std::move(c));
    }
  }
  return out;
}

// Span and basis/derivative rows of one build on one case.
struct Rows {
  std::vector<int> spans;
  std::vector<std::vector<double>> basis, ders;
};

template <typename T>
Rows cpp_build(const Case& c) {
  const std::vector<T> k(c.knots.begin(), c.knots.end());
  const int count = static_cast<int>(k.size()) - c.degree - 1;
  Rows r;
  for (double u : c.u) {
    const T x = static_cast<T>(u);
    const int span = tb_find_span(c.degree, count, k.data(), x);
    T b[TB_MAX_ORDER], d[TB_MAX_ORDER];
    tb_basis(span, x, c.degree, k.data(), b, d, true);
    r.spans.push_back(span);
    r.basis.emplace_back(b, b + c.degree + 1);
    r.ders.emplace_back(d, d + c.degree + 1);
  }
  return r;
}

std::vector<Rows> glsl_build(const std::vector<Case>& all, bool f64) {
  std::vector<vk_compute::BasisJob> jobs;
  for (const Case& c : all) jobs.push_back({c.knots, c.degree, c.u});
  const std::vector<vk_compute::BasisRun> runs = vk_compute::basis_on_vulkan(jobs, f64, 0);
  std::vector<Rows> out;
  for (std::size_t i = 0; i < all.size(); ++i) {
    Rows& r = out.emplace_back();
    r.spans = runs[i].spans;
    for (std::size_t k = 0; k < all[i].u.size(); ++k) {
      const double* v = runs[i].values.data() + k * TB_STRIDE;
      r.basis.emplace_back(v, v + all[i].degree + 1);
      r.ders.emplace_back(v + TB_MAX_ORDER, v + TB_MAX_ORDER + all[i].degree + 1);
    }
  }
  return out;
}

// The reference on the knots and parameters rounded to T: A2.1 and A2.3 in long double.
template <typename T>
Rows oracle(const Case& c) {
  std::vector<long double> k;
  for (double x : c.knots) k.push_back(static_cast<long double>(static_cast<T>(x)));
  const int count = static_cast<int>(k.size()) - c.degree - 1;
  Rows r;
  for (double u : c.u) {
    const long double x = static_cast<long double>(static_cast<T>(u));
    const int span = find_span(c.degree, count, k.data(), x);
    long double d[3][kMaxOrder];
    basis_function_derivatives(span, x, c.degree, 1, k.data(), d);
    r.spans.push_back(span);
    r.basis.emplace_back(d[0], d[0] + c.degree + 1);
    r.ders.emplace_back(d[1], d[1] + c.degree + 1);
  }
  return r;
}

// Largest difference of values (basis: absolute, they lie in [0, 1]; derivatives: relative to the
// row's largest reference derivative, which grows as 1/h on short spans).
struct Worst {
  double basis = 0, derivative = 0;
  int span_mismatches = 0;
};

void compare(const Rows& a, const Rows& b, const Rows& scale, Worst& w) {
  for (std::size_t k = 0; k < a.spans.size(); ++k) {
    w.span_mismatches += a.spans[k] != b.spans[k] ? 1 : 0;
    double s = 0;
    for (double d : scale.ders[k]) s = std::max(s, std::fabs(d));
    for (std::size_t j = 0; j < a.basis[k].size(); ++j) {
      w.basis = std::max(w.basis, std::fabs(a.basis[k][j] - b.basis[k][j]));
      w.derivative = std::max(w.derivative, std::fabs(a.ders[k][j] - b.ders[k][j]) / s);
    }
  }
}

template <typename T>
void check_cpp(double basis_bound, double derivative_bound) {
  Worst w;
  for (const Case& c : cases()) compare(cpp_build<T>(c), oracle<T>(c), oracle<T>(c), w);
  std::printf("tensor basis C++ %s vs reference: basis %.3g, derivative %.3g\n",
              sizeof(T) == 4 ? "float" : "double", w.basis, w.derivative);
  EXPECT_EQ(w.span_mismatches, 0);
  EXPECT_LT(w.basis, basis_bound);
  EXPECT_LT(w.derivative, derivative_bound);
}

TEST(vk_compute_basis_cpp, MatchesTheReference) {
  check_cpp<float>(2e-6, 2e-5);
  check_cpp<double>(4e-15, 4e-14);
}

template <typename T>
void check_glsl(double basis_bound, double derivative_bound, double between_bound) {
  const bool f64 = sizeof(T) == 8;
  Worst vs_reference, vs_cpp;
  const std::vector<Case> all = cases();
  const std::vector<Rows> glsl = glsl_build(all, f64);
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Rows ref = oracle<T>(all[i]);
    compare(glsl[i], ref, ref, vs_reference);
    compare(glsl[i], cpp_build<T>(all[i]), ref, vs_cpp);
  }
  std::printf("tensor basis GLSL %s vs reference: basis %.3g, derivative %.3g\n",
              f64 ? "f64" : "f32", vs_reference.basis, vs_reference.derivative);
  std::printf("tensor basis GLSL %s vs C++: basis %.3g, derivative %.3g\n", f64 ? "f64" : "f32",
              vs_cpp.basis, vs_cpp.derivative);
  EXPECT_EQ(vs_reference.span_mismatches, 0);
  EXPECT_EQ(vs_cpp.span_mismatches, 0);
  EXPECT_LT(vs_reference.basis, basis_bound);
  EXPECT_LT(vs_reference.derivative, derivative_bound);
  EXPECT_LT(std::max(vs_cpp.basis, vs_cpp.derivative), between_bound);
}

TEST(vk_compute_basis_glsl, MatchesTheReferenceAndTheCppBuildF32) {
  const Availability a = find_strategy("vk-compute")->probe();
  if (!a.available) GTEST_SKIP() << a.reason;
  check_glsl<float>(2e-6, 2e-5, 2e-5);
}

TEST(vk_compute_basis_glsl, MatchesTheReferenceAndTheCppBuildF64) {
  const Availability a = find_strategy("vk-compute")->probe();
  if (!a.available) GTEST_SKIP() << a.reason;
  try {
    check_glsl<double>(4e-15, 4e-14, 4e-14);
  } catch (const RefusedError& e) {
    GTEST_SKIP() << e.what();
  }
}

}  // namespace
}  // namespace nurbs
