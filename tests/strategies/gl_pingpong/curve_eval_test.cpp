// gl-pingpong's curve path (000 §2.2, strategies/gl_pingpong/curve_eval.h) against A4.1 in double
// (nurbs::curve_point) at the same float parameter the GPU sees: degrees 1, 2, 3, 5, 9 and 15 (the
// validation limit; the knot array is 2k+1 = 33 texels wide there), random weights in [0.25, 4],
// a knot repeated `degree` times inside (0/0 terms in the recursion), parameters on every knot and
// at both ends, both reductions, OSMesa and EGL. Errors are in float ulps of the curve's size (the
// largest side of its control points' bounding box). The pass count is read from the draws issued
// (gl::DrawCounts): k-1 basis passes, one multiply, ceil(log2 k) pairwise reduction passes (or
// one), one divide, per chunk.
#include "strategies/gl_pingpong/curve_eval.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "reference/sampling.h"
#include "reference/validation.h"
#include "strategies/gl_context/gl_context.h"
#include "tests/reference/test_support.h"

namespace nurbs {
namespace {

using gl_pingpong::CurveEvaluator;
using gl_pingpong::Reduction;

// Measured worst over every case below: 28.9 ulps (degree 9, u = 0.432006; the same on OSMesa and
// EGL and for both reductions, so the knots' and basis passes' float rounding dominates, not the
// summation order); about 4x that.
constexpr double kBudgetUlp = 120.0;

struct Case {
  std::string platform;
  Reduction reduction;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << c.platform << "/" << to_string(c.reduction);
}

// Random control points in [-3, 5]^3, weights in [0.25, 4], crease knots (test_support.h).
Curve random_curve(int degree, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coordinate(-3.0, 5.0),
      log_weight(std::log(0.25), std::log(4.0));
  Curve c;
  c.degree = degree;
  const int count = 3 * degree + 4;
  c.knots = test::knots_with_crease(degree, count);
  for (int i = 0; i < count; ++i) {
    const double w = std::exp(log_weight(rng));
    c.homogeneous.push_back({w * coordinate(rng), w * coordinate(rng), w * coordinate(rng), w});
  }
  return c;
}

double curve_size(const Curve& c) {
  double size = 0;
  for (int axis = 0; axis < 3; ++axis) {
    double lo = INFINITY, hi = -INFINITY;
    for (const Vec4<double>& p : c.homogeneous) {
      lo = std::min(lo, p[axis] / p[3]);
      hi = std::max(hi, p[axis] / p[3]);
    }
    size = std::max(size, hi - lo);
  }
  return size;
}

// A grid over the domain, every knot of the domain, and the two ends once more.
std::vector<double> curve_parameters(const Curve& c, int grid) {
  std::vector<double> u = grid_parameters(c.start(), c.end(), grid);
  for (int i = c.degree; i <= c.count(); ++i) u.push_back(c.knots[static_cast<std::size_t>(i)]);
  u.push_back(c.start());
  u.push_back(c.end());
  return u;
}

StrategyOptions options_for(const std::string& platform, int tile = 0) {
  StrategyOptions o;
  o.extra["gl"] = platform;
  if (tile > 0) o.extra["tile"] = std::to_string(tile);
  return o;
}

bool skip_unless_available(const std::string& platform, std::string& reason) {
  const Availability a = gl::Context::probe(*gl::parse_platform(platform));
  reason = a.reason;
  return !a.available;
}

class CurveEval : public ::testing::TestWithParam<Case> {};

TEST_P(CurveEval, MatchesTheDoubleCurvePointWithinTheBudget) {
  const Case c = GetParam();
  std::string reason;
  if (skip_unless_available(c.platform, reason)) GTEST_SKIP() << "unavailable: " << reason;
  CurveEvaluator gpu(options_for(c.platform), c.reduction);
  test::Worst worst("curve ulps of size");
  for (int degree : {1, 2, 3, 5, 9, 15}) {
    const Curve curve = random_curve(degree, 1000u + static_cast<unsigned>(degree));
    const std::vector<double> u = curve_parameters(curve, 257);
    gpu.prepare(curve, u);
    gpu.evaluate();
    const std::vector<Vec3<float>> got = gpu.read_back();
    ASSERT_EQ(got.size(), u.size());
    const double size = curve_size(curve);
    const double ulp =
        std::nextafter(static_cast<float>(size), INFINITY) - static_cast<float>(size);
    for (std::size_t q = 0; q < u.size(); ++q) {
      // The GPU evaluates at the float parameter: so does the reference, so the measure is the
      // float pipeline's error, not the parameter's rounding times the speed.
      const double uf = static_cast<float>(u[q]);
      const Vec3<double> want = curve_point(curve, uf);
      double err = 0;
      for (int i = 0; i < 3; ++i) err = std::max(err, std::abs(double(got[q][i]) - want[i]));
      const double ulps = err / ulp;
      worst.update(ulps, [&] { return fmt::format("degree {} u={}", degree, uf); });
      ASSERT_TRUE(ulps <= kBudgetUlp)
          << "degree " << degree << " u=" << uf << ": got (" << got[q][0] << ", " << got[q][1]
          << ", " << got[q][2] << "), reference (" << want[0] << ", " << want[1] << ", " << want[2]
          << "): " << ulps << " ulps of size " << size;
    }
  }
}

// Chunked (tile 100 rows: 3 chunks for 260 parameters) gives the same points as unchunked, and
// every chunk draws its k-1 basis passes, one multiply, the reduction passes and one divide.
TEST_P(CurveEval, PassesCountedFromTheDrawsIssued) {
  const Case c = GetParam();
  std::string reason;
  if (skip_unless_available(c.platform, reason)) GTEST_SKIP() << "unavailable: " << reason;
  CurveEvaluator whole(options_for(c.platform), c.reduction);
  CurveEvaluator tiled(options_for(c.platform, 100), c.reduction);
  for (int degree : {1, 2, 3, 5, 9, 15}) {
    const Curve curve = random_curve(degree, 2000u + static_cast<unsigned>(degree));
    std::vector<double> u = grid_parameters(curve.start(), curve.end(), 260);
    whole.prepare(curve, u);
    tiled.prepare(curve, u);
    whole.evaluate();
    tiled.evaluate();
    const int order = degree + 1;
    const std::uint64_t reduction =
        c.reduction == Reduction::pairwise
            ? static_cast<std::uint64_t>(std::ceil(std::log2(static_cast<double>(order))))
            : 1;
    for (const auto& [e, chunks] : {std::pair<CurveEvaluator*, std::uint64_t>{&whole, 1},
                                    std::pair<CurveEvaluator*, std::uint64_t>{&tiled, 3}}) {
      const gl_pingpong::CurvePasses p = e->passes();
      EXPECT_EQ(p.basis, chunks * static_cast<std::uint64_t>(degree)) << "degree " << degree;
      EXPECT_EQ(p.multiply, chunks) << "degree " << degree;
      EXPECT_EQ(p.reduction, chunks * reduction) << "degree " << degree;
      EXPECT_EQ(p.divide, chunks) << "degree " << degree;
    }
    const std::vector<Vec3<float>> a = whole.read_back(), b = tiled.read_back();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t q = 0; q < a.size(); ++q)
      for (int i = 0; i < 3; ++i)
        ASSERT_EQ(a[q][i], b[q][i]) << "degree " << degree << " parameter " << q;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Platforms, CurveEval,
    ::testing::Values(Case{"osmesa", Reduction::pairwise}, Case{"osmesa", Reduction::single_pass},
                      Case{"egl", Reduction::pairwise}, Case{"egl", Reduction::single_pass}),
    [](const auto& info) {
      std::string name = info.param.platform + "_" + std::string(to_string(info.param.reduction));
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

// Bad input is an InputError naming the field, index and value, before anything is uploaded.
TEST(CurveEvalInput, RejectsBadCurvesAndParameters) {
  std::string reason;
  if (skip_unless_available("osmesa", reason)) GTEST_SKIP() << "unavailable: " << reason;
  CurveEvaluator gpu(options_for("osmesa"));
  const Curve good = random_curve(3, 7);
  const auto expect_error = [&](const Curve& curve, const std::vector<double>& u,
                                const std::string& names) {
    try {
      gpu.prepare(curve, u);
      ADD_FAILURE() << "accepted; expected an error naming " << names;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(names), std::string::npos) << e.what();
    }
  };
  Curve bad_knot = good;
  bad_knot.knots[5] = 2.0;  // the next knot is then smaller
  expect_error(bad_knot, {0.5}, "knots[6] = ");
  Curve bad_weight = good;
  bad_weight.homogeneous[4][3] = 0.0;
  expect_error(bad_weight, {0.5}, "points[4][3] = 0");
  Curve high = good;
  high.degree = 16;
  expect_error(high, {0.5}, "degree = 16");
  expect_error(good, {0.5, NAN}, "parameters[1] = nan");
}

}  // namespace
}  // namespace nurbs
