// cpu-horner (Macri 1999, 004): the power-basis coefficients reproduce the B-spline basis, and
// the accuracy-versus-degree curve of both expansions (about the span's left knot, the default,
// and about 0, Macri's literal A0 + A1 u + ...), measured against the reference, printed, and
// held at every degree to an error bound derived from the coefficients (Horner's running error
// bound carried to the rational point).
#include <gtest/gtest.h>

#include <cfloat>
#include <cstdio>
#include <limits>
#include <random>

#include "harness/metrics.h"
#include "reference/nurbs_math.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "strategies/cpu_horner/power_basis.h"
#include "strategies/registry.h"

namespace nurbs {
namespace {

TEST(CpuHornerPowerBasis, CoefficientsReproduceTheBasisFunctions) {
  const Surface s = make_builtin_scene("patch144")->surfaces[0];
  std::mt19937_64 rng(7);
  for (long double origin_shift : {0.0L, 1.0L}) {
    for (int span = s.degree_u; span < s.count_u; ++span) {
      const double lo = s.knots_u[span], hi = s.knots_u[span + 1];
      if (!(lo < hi)) continue;
      const long double origin = origin_shift == 0 ? lo : 0.0L;
      const auto c = horner::power_basis_coefficients(s.knots_u, s.degree_u, span, origin);
      std::uniform_real_distribution<double> du(lo, hi);
      for (int trial = 0; trial < 20; ++trial) {
        const long double u = du(rng);
        long double expected[kMaxOrder], ders[3][kMaxOrder]{}, values[kMaxOrder], d[kMaxOrder];
        std::vector<long double> knots(s.knots_u.begin(), s.knots_u.end());
        basis_functions(span, u, s.degree_u, knots.data(), expected);
        basis_function_derivatives(span, u, s.degree_u, 1, knots.data(), ders);
        horner::horner_basis(c.data(), s.degree_u, u - origin, values, d);
        for (int k = 0; k <= s.degree_u; ++k) {
          EXPECT_NEAR(static_cast<double>(values[k]), static_cast<double>(expected[k]), 1e-15);
          EXPECT_NEAR(static_cast<double>(d[k]), static_cast<double>(ders[1][k]),
                      1e-15 * std::max(1.0, std::fabs(static_cast<double>(ders[1][k]))) * 100);
        }
      }
    }
  }
}

// The builtin degree-N scenes' 16x16 net at any degree up to 15, uniform clamped knots.
Scene degree_scene(int degree) {
  Scene scene = *make_builtin_scene("degree-9");
  Surface& s = scene.surfaces[0];
  auto knots = [&](int count) {
    std::vector<double> k(degree + 1, 0.0);
    const int interior = count - degree - 1;
    for (int i = 1; i <= interior; ++i) k.push_back(double(i) / (interior + 1));
    k.insert(k.end(), degree + 1, 1.0);
    return k;
  };
  s.degree_u = s.degree_v = degree;
  s.knots_u = knots(s.count_u);
  s.knots_v = knots(s.count_v);
  scene.name = "degree-" + std::to_string(degree);
  return scene;
}

// The grid of the accuracy tests: 33 x 33 on the degree scenes' [0, 1] domain, so every
// parameter i/32 is exact in float and the error is Horner's, not the parameter's rounding.
Sampling accuracy_grid() {
  Sampling grid;
  grid.grid_u = 33;
  grid.grid_v = 33;
  return grid;
}

// Max error in ulps of the scene's largest coordinate, in the precision's own ulps.
double max_ulp(const std::string& strategy, const Scene& scene, Precision precision,
               const std::map<std::string, std::string>& extra) {
  StrategyOptions options;
  options.extra = extra;
  auto s = find_strategy(strategy)->create(options);
  s->prepare(scene, EvalRequest{accuracy_grid(), precision, false});
  s->evaluate();
  const auto reference =
      evaluate_reference(scene, sample_parameters(scene, accuracy_grid()), false);
  const double ulp = measure_accuracy(scene, s->read_back(), reference).max_ulp;
  return precision == Precision::f64 ? ulp * FLT_EPSILON / DBL_EPSILON : ulp;
}

// Per grid parameter, the sum over the p+1 non-zero basis functions of a bound on the error of
// cpu-horner's value in T: Horner's running error bound (Higham, Accuracy and Stability of
// Numerical Algorithms, Algorithm 5.1: mu_p = |y_p|/2, mu_j = |t| mu_(j+1) + |y_j|, error <=
// u (2 mu_0 - |y_0|)), computed along the same recurrence in T as power_basis.h, plus the
// coefficients' rounding to T (sum |c^_j - c_j| |t|^j) and the parameter's (t = u - origin in
// T against the exact one: the exact polynomial's difference between the two), both in long
// double. Computed from the coefficients alone, never from the strategy's output.
template <typename T>
long double horner_value_bound(const std::vector<long double>& c, int p, int k, double u,
                               long double o) {
  const long double unit = std::numeric_limits<T>::epsilon() / 2.0L;
  const T t_rounded = T(u) - T(o);  // as PowerBasisTable::evaluate forms it
  const long double t = u - o, tr = t_rounded;
  auto coefficient = [&](int j) { return c[j * (p + 1) + k]; };
  T y = T(coefficient(p));
  long double mu = std::fabs(static_cast<long double>(y)) / 2;
  long double exact_at_t = coefficient(p), exact_at_tr = coefficient(p), stored = 0;
  for (int j = p - 1; j >= 0; --j) {
    y = y * t_rounded + T(coefficient(j));
    mu = std::fabs(tr) * mu + std::fabs(static_cast<long double>(y));
    exact_at_t = exact_at_t * t + coefficient(j);
    exact_at_tr = exact_at_tr * tr + coefficient(j);
  }
  for (int j = 0; j <= p; ++j)
    stored += std::fabs(static_cast<long double>(T(coefficient(j))) - coefficient(j)) *
              std::pow(std::fabs(tr), j);
  return unit * (2 * mu - std::fabs(static_cast<long double>(y))) + stored +
         std::fabs(exact_at_tr - exact_at_t);
}

template <typename T>
std::vector<long double> basis_error_bounds(const Scene& scene, const std::vector<double>& knots,
                                            int p, int count, horner::Origin origin) {
  std::vector<long double> out;
  const auto samples = sample_parameters(scene, accuracy_grid());
  for (double u : samples[0].u) {
    const int span = find_span(p, count, knots.data(), u);
    const long double o = origin == horner::Origin::span_start ? knots[span] : 0.0L;
    const auto c = horner::power_basis_coefficients(knots, p, span, o);
    long double total = 0;
    for (int k = 0; k <= p; ++k) total += horner_value_bound<T>(c, p, k, u, o);
    out.push_back(total);
  }
  return out;
}

// A bound on cpu-horner's error over the grid, in the same ulps as max_ulp, from the basis
// bounds above: with unit weights the homogeneous sum of (p+1)(q+1) products errs by
// max|P| (e_u + e_v + e_u e_v) plus its own rounding gamma(p+q+2) max|P| (1+e_u)(1+e_v), w by
// the same expression without max|P|, and the divide by the computed w adds w's error relative to
// the point; Euclidean over the three coordinates. The factor 1.01 covers dropped second-order
// terms. Rounding the control points to T adds u max|P| (half an ulp), inside the 1.01.
double horner_error_bound_ulps(const Scene& scene, horner::Origin origin, Precision precision) {
  const Surface& s = scene.surfaces.at(0);
  for (double w : s.weights) EXPECT_EQ(w, 1.0) << "the bound assumes unit weights";
  const bool f32 = precision == Precision::f32;
  const long double unit = f32 ? FLT_EPSILON / 2.0L : DBL_EPSILON / 2.0L;
  auto gamma = [&](int n) { return n * unit / (1 - n * unit); };
  auto basis_error = [&](const std::vector<double>& knots, int p, int count) {
    return f32 ? basis_error_bounds<float>(scene, knots, p, count, origin)
               : basis_error_bounds<double>(scene, knots, p, count, origin);
  };
  const auto eu = basis_error(s.knots_u, s.degree_u, s.count_u);
  const auto ev = basis_error(s.knots_v, s.degree_v, s.count_v);
  long double largest_point = 0;
  for (const Point3& p : s.points)
    for (double c : p) largest_point = std::max<long double>(largest_point, std::fabs(c));
  long double worst = 0;
  for (long double a : eu)
    for (long double b : ev) {
      const long double products = a + b + a * b;
      const long double sum = gamma(s.degree_u + s.degree_v + 2) * (1 + a) * (1 + b);
      const long double numerator = largest_point * (products + sum);  // per coordinate
      const long double w_error = products + sum;                      // w = 1 exactly
      // A computed w that may be 0 bounds nothing: Macri's expansion about 0 gets there in f32
      // from degree 10 on (basis errors of hundreds), and the bound says "unbounded".
      if (w_error >= 1) return std::numeric_limits<double>::infinity();
      const long double point =
          (numerator + largest_point * w_error) / (1 - w_error) + unit * largest_point;
      worst = std::max(worst, std::sqrt(3.0L) * point);  // Euclidean over three coordinates
    }
  const double ulp =
      (precision == Precision::f32 ? FLT_EPSILON : DBL_EPSILON) * scene.largest_coordinate();
  return static_cast<double>(1.01L * worst / ulp);
}

// The accuracy-versus-degree curve of both expansions, printed, and each measured figure held to
// its derived bound: span-local coefficients stay small, so their bound (and error) stays low;
// Macri's expansion about 0 grows with the degree, and the bound says by how much it may.
TEST(CpuHornerPowerBasis, AccuracyVersusDegreeWithinTheDerivedBound) {
  std::printf(
      "degree | horner span f32 (bound) | horner zero f32 (bound) | coxdeboor f32 | "
      "horner span f64 (bound) | horner zero f64 (bound) | coxdeboor f64   (f32: float ulps, "
      "f64: double ulps)\n");
  const std::map<std::string, std::string> zero{{"horner-origin", "zero"}};
  for (int degree = 1; degree <= kMaxDegree; ++degree) {
    const Scene scene = degree_scene(degree);
    struct Row {
      double measured, bound;
    };
    auto row = [&](Precision precision, horner::Origin origin) {
      const auto extra =
          origin == horner::Origin::zero ? zero : std::map<std::string, std::string>{};
      return Row{max_ulp("cpu-horner", scene, precision, extra),
                 horner_error_bound_ulps(scene, origin, precision)};
    };
    const Row span32 = row(Precision::f32, horner::Origin::span_start);
    const Row zero32 = row(Precision::f32, horner::Origin::zero);
    const Row span64 = row(Precision::f64, horner::Origin::span_start);
    const Row zero64 = row(Precision::f64, horner::Origin::zero);
    const double cox32 = max_ulp("cpu-coxdeboor", scene, Precision::f32, {});
    const double cox64 = max_ulp("cpu-coxdeboor", scene, Precision::f64, {});
    std::printf(
        "%6d | %9.3g (%9.3g) | %9.3g (%9.3g) | %13.3g | %9.3g (%9.3g) | %9.3g (%9.3g) | %13.3g\n",
        degree, span32.measured, span32.bound, zero32.measured, zero32.bound, cox32,
        span64.measured, span64.bound, zero64.measured, zero64.bound, cox64);
    for (const auto& [name, r] : {std::pair{"span f32", span32}, std::pair{"zero f32", zero32},
                                  std::pair{"span f64", span64}, std::pair{"zero f64", zero64}})
      EXPECT_LE(r.measured, r.bound) << name << ", degree " << degree;
    // The default (span-local) expansion stays within the CPU bound over the builtin degrees.
    if (degree <= 9) {
      EXPECT_LE(span32.measured, 32.0) << "degree " << degree;
      EXPECT_LE(span64.measured, 64.0) << "degree " << degree;
    }
  }
}

// Forward differences (004's alternative for the basis tables) on every span of a degree-p knot
// vector, at the parameters i/1024, against the exact basis in long double. The bound runs the
// rounding through the method's recurrence, with the differences' sizes bounded by the mean value
// theorem (|Delta^j f| <= h^j max |f^(j)|, the derivative bounded by its coefficients' magnitudes
// over the run): each starting difference is rounded once to T (u h^j M_j), and every step's
// d_j += d_(j+1) adds its operands' bounds plus one rounding of a result no larger than
// h^j M_j plus those bounds.
template <typename T>
void expect_forward_differences_within_bound(int p, long double& worst_error,
                                             long double& worst_bound) {
  const Surface s = degree_scene(p).surfaces[0];
  const long double unit = std::numeric_limits<T>::epsilon() / 2.0L;
  const long double h = 1.0L / 1024;
  const int lanes = p + 1;
  for (int span = p; span < s.count_u; ++span) {
    std::vector<double> run;
    for (int i = 0; i <= 1024; ++i) {
      const double u = i / 1024.0;
      if (find_span(p, s.count_u, s.knots_u.data(), u) == span) run.push_back(u);
    }
    const int steps = static_cast<int>(run.size());
    if (steps <= p + 1) continue;
    const long double o = s.knots_u[span];
    const auto c = horner::power_basis_coefficients(s.knots_u, p, span, o);
    auto exact = [&](int k, double u) {
      long double y = c[p * lanes + k];
      for (int j = p - 1; j >= 0; --j) y = y * (u - o) + c[j * lanes + k];
      return y;
    };
    std::vector<T> out(static_cast<std::size_t>(steps) * lanes);
    horner::forward_differences(c.data(), p, lanes, run[0] - o, h, steps, out.data());
    const long double reach = std::max(std::fabs(run[0] - o), std::fabs(run.back() + p * h - o));
    for (int k = 0; k < lanes; ++k) {
      std::vector<long double> size(lanes), e(lanes);  // h^j M_j, and the bounds
      for (int j = 0; j <= p; ++j) {
        long double derivative = 0;
        for (int m = j; m <= p; ++m) {
          long double falling = 1;
          for (int r = 0; r < j; ++r) falling *= m - r;
          derivative += std::fabs(c[m * lanes + k]) * falling * std::pow(reach, m - j);
        }
        size[j] = std::pow(h, j) * derivative;
        e[j] = unit * size[j];
      }
      for (int step = 0; step < steps; ++step) {
        const long double error = std::fabs(out[step * lanes + k] - exact(k, run[step]));
        EXPECT_LE(error, 1.01L * e[0])
            << "degree " << p << " span " << span << " basis " << k << " step " << step;
        worst_error = std::max(worst_error, error);
        worst_bound = std::max(worst_bound, e[0]);
        for (int j = 0; j < p; ++j) e[j] = e[j] + e[j + 1] + unit * (size[j] + e[j] + e[j + 1]);
      }
    }
  }
}

TEST(CpuHornerForwardDifferences, WithinTheirRunningBoundAtEveryDegree) {
  std::printf("degree | f32 error (bound) | f64 error (bound)   (basis values, 1025 parameters)\n");
  for (int p = 1; p <= kMaxDegree; ++p) {
    long double e32 = 0, b32 = 0, e64 = 0, b64 = 0;
    expect_forward_differences_within_bound<float>(p, e32, b32);
    expect_forward_differences_within_bound<double>(p, e64, b64);
    std::printf("%6d | %9.3Lg (%9.3Lg) | %9.3Lg (%9.3Lg)\n", p, e32, b32, e64, b64);
  }
}

// The strategy with forward-differenced tables lands on the surface where the bound says it is
// good (the default tables elsewhere), and keeps the domain's end exact (the crack test's edge).
TEST(CpuHornerForwardDifferences, StrategyMatchesHornerTablesOnACubic) {
  const Scene scene = *make_builtin_scene("patch144");
  Sampling grid;
  grid.grid_u = grid.grid_v = 257;
  for (Precision precision : {Precision::f32, Precision::f64}) {
    auto run = [&](const char* tables) {
      StrategyOptions options;
      options.extra = {{"horner-tables", tables}};
      auto s = find_strategy("cpu-horner")->create(options);
      s->prepare(scene, EvalRequest{grid, precision, false});
      s->evaluate();
      return s->read_back();
    };
    const auto reference = evaluate_reference(scene, sample_parameters(scene, grid), false);
    const double horner = measure_accuracy(scene, run("horner"), reference).max_ulp;
    const double differences =
        measure_accuracy(scene, run("forward-differences"), reference).max_ulp;
    std::printf("patch144 257x257 %s: horner tables %.3g ulps, forward differences %.3g ulps\n",
                precision == Precision::f32 ? "f32" : "f64", horner, differences);
    EXPECT_LE(differences, precision == Precision::f32 ? 32.0 : 1e-6);
  }
}

// 004's explicit SSE form and the compiler's loop round the same operations in the same order:
// identical points and normals, in both precisions, on a rational multi-span surface.
TEST(CpuHornerSimd, ExplicitSseEqualsTheLoopBitForBit) {
  const Scene scene = *make_builtin_scene("patch144");
  for (Precision precision : {Precision::f32, Precision::f64}) {
    auto run = [&](const char* simd) {
      StrategyOptions options;
      options.extra = {{"horner-simd", simd}};
      auto s = find_strategy("cpu-horner")->create(options);
      s->prepare(scene, EvalRequest{accuracy_grid(), precision, true});
      s->evaluate();
      return s->read_back();
    };
    EvalResult loop = run("auto"), sse;
    try {
      sse = run("explicit");
    } catch (const RefusedError& e) {
      GTEST_SKIP() << e.what();  // a build without SSE2 says so instead
    }
    const auto& a = loop.surfaces[0];
    const auto& b = sse.surfaces[0];
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t k = 0; k < a.positions.size(); ++k) {
      ASSERT_EQ(a.positions[k], b.positions[k]) << k;
      ASSERT_EQ(a.normals[k], b.normals[k]) << k;
    }
  }
}

TEST(CpuHornerSimd, UnknownValueIsRefusedNamingIt) {
  StrategyOptions options;
  options.extra = {{"horner-simd", "avx"}};
  try {
    find_strategy("cpu-horner")->create(options);
    FAIL() << "horner-simd=avx was accepted";
  } catch (const RefusedError& e) {
    EXPECT_NE(std::string(e.what()).find("horner-simd = 'avx'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace nurbs
