// cpu-horner (Macri 1999, 004): the power-basis coefficients reproduce the B-spline basis, and
// the accuracy-versus-degree curve of both expansions (about the span's left knot, the default,
// and about 0, Macri's literal A0 + A1 u + ...), measured against the reference and printed.
#include <gtest/gtest.h>

#include <cfloat>
#include <cstdio>
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

double max_ulp(const std::string& strategy, const Scene& scene, Precision precision,
               const std::map<std::string, std::string>& extra) {
  Sampling grid;
  grid.grid_u = 33;
  grid.grid_v = 29;
  StrategyOptions options;
  options.extra = extra;
  auto s = find_strategy(strategy)->create(options);
  s->prepare(scene, EvalRequest{grid, precision, false});
  s->evaluate();
  const auto reference = evaluate_reference(scene, sample_parameters(scene, grid), false);
  const double ulp = measure_accuracy(scene, s->read_back(), reference).max_ulp;
  // f64 in double ulps of the largest coordinate, f32 in float ulps.
  return precision == Precision::f64 ? ulp * FLT_EPSILON / DBL_EPSILON : ulp;
}

TEST(CpuHornerPowerBasis, AccuracyVersusDegree) {
  std::printf(
      "degree | horner span f32 | horner zero f32 | coxdeboor f32 | horner span f64 | "
      "horner zero f64 | coxdeboor f64   (f32: float ulps, f64: double ulps)\n");
  for (int degree = 1; degree <= kMaxDegree; ++degree) {
    const Scene scene = degree_scene(degree);
    const double span32 = max_ulp("cpu-horner", scene, Precision::f32, {});
    const double zero32 = max_ulp("cpu-horner", scene, Precision::f32, {{"horner-origin", "zero"}});
    const double cox32 = max_ulp("cpu-coxdeboor", scene, Precision::f32, {});
    const double span64 = max_ulp("cpu-horner", scene, Precision::f64, {});
    const double zero64 = max_ulp("cpu-horner", scene, Precision::f64, {{"horner-origin", "zero"}});
    const double cox64 = max_ulp("cpu-coxdeboor", scene, Precision::f64, {});
    std::printf("%6d | %15.3g | %15.3g | %13.3g | %15.3g | %15.3g | %13.3g\n", degree, span32,
                zero32, cox32, span64, zero64, cox64);
    // The default (span-local) expansion stays within the CPU bound over the builtin degrees.
    if (degree <= 9) {
      EXPECT_LE(span32, 32.0) << "degree " << degree;
      EXPECT_LE(span64, 64.0) << "degree " << degree;
    }
  }
}

}  // namespace
}  // namespace nurbs
