// reference/bezier_decomposition.h (The NURBS Book A5.6/A5.7) against independent checks: every
// Bézier patch evaluated by the closed-form Bernstein polynomials C(p,i) t^i (1-t)^(p-i) (not the
// code under test, not de Casteljau) equals the reference surface point at the same (u, v), on
// random rational surfaces of degrees 1..9 with repeated and unclamped knots; the patch count is
// the number of distinct-breakpoint intervals; small cases computed by hand.
#include "reference/bezier_decomposition.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "random_nurbs.h"
#include "reference/validation.h"
#include "test_support.h"

namespace nurbs::test {
namespace {

using LD = long double;

LD binomial(int n, int k) {
  LD c = 1;
  for (int i = 1; i <= k; ++i) c = c * (n - k + i) / i;
  return c;
}

LD bernstein(int p, int i, LD t) {
  return binomial(p, i) * std::pow(t, i) * std::pow(1 - t, p - i);
}

// Rational Bézier point of one patch at local (t, s) in [0, 1]^2, Bernstein closed form.
Vec3<LD> bezier_point(const BezierPatches<LD>& b, int g, int h, LD t, LD s) {
  const Vec4<LD>* pts = b.patch(g, h);
  Vec4<LD> sum{};
  for (int k = 0; k <= b.degree_u; ++k)
    for (int l = 0; l <= b.degree_v; ++l) {
      const LD basis = bernstein(b.degree_u, k, t) * bernstein(b.degree_v, l, s);
      for (int c = 0; c < 4; ++c) sum[c] += basis * pts[k * (b.degree_v + 1) + l][c];
    }
  return {sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3]};
}

// The breakpoints of the domain, found without the code under test: distinct knot values in
// [knots[degree], knots[count]].
std::vector<double> breakpoints(const std::vector<double>& knots, int degree, int count) {
  std::set<double> distinct;
  for (double k : knots)
    if (k >= knots[degree] && k <= knots[count]) distinct.insert(k);
  return {distinct.begin(), distinct.end()};
}

// Segment of parameter t among breakpoints, any one containing it (at a shared breakpoint both
// patches must agree, so the choice is free; take the one starting there unless t is the end).
int segment_of(const std::vector<double>& breaks, double t) {
  int g = 0;
  while (g + 2 < static_cast<int>(breaks.size()) && t >= breaks[g + 1]) ++g;
  return g;
}

TEST(BezierDecomposition, RandomRationalSurfacesMatchTheReferencePointwise) {
  Rng rng(20261201);
  Worst worst("max |Bezier - reference| / largest coordinate (long double)");
  int surfaces = 0;
  for (int degree_u = 1; degree_u <= 9; ++degree_u)
    for (int trial = 0; trial < 6; ++trial) {
      const int degree_v = uniform_int(rng, 1, 9);
      const int count_u = degree_u + 1 + uniform_int(rng, 0, 6);
      const int count_v = degree_v + 1 + uniform_int(rng, 0, 6);
      const Ends ends = trial % 3 == 0   ? Ends::clamped
                        : trial % 3 == 1 ? Ends::unclamped
                                         : Ends::mixed;
      const Surface s =
          random_surface(rng, degree_u, degree_v, count_u, count_v, ends, /*rational=*/true);
      validate_surface(s, 0, "random");
      ++surfaces;
      const SurfaceNet<LD> net(s);
      const BezierPatches<LD> b = decompose_surface(net);

      const std::vector<double> breaks_u = breakpoints(s.knots_u, degree_u, count_u);
      const std::vector<double> breaks_v = breakpoints(s.knots_v, degree_v, count_v);
      ASSERT_EQ(b.segments_u, static_cast<int>(breaks_u.size()) - 1);
      ASSERT_EQ(b.segments_v, static_cast<int>(breaks_v.size()) - 1);
      EXPECT_EQ(ksquad_count(s), (breaks_u.size() - 1) * (breaks_v.size() - 1));
      ASSERT_EQ(b.points.size(), b.patch_count() * (degree_u + 1) * (degree_v + 1));

      LD scale = 0;
      for (const Point3& p : s.points)
        for (double c : p) scale = std::max<LD>(scale, std::fabs(c));
      const auto us = test_parameters(rng, s.knots_u, degree_u, count_u, 12);
      const auto vs = test_parameters(rng, s.knots_v, degree_v, count_v, 12);
      for (double u : us)
        for (double v : vs) {
          const int g = segment_of(breaks_u, u), h = segment_of(breaks_v, v);
          const LD t = (LD(u) - breaks_u[g]) / (LD(breaks_u[g + 1]) - breaks_u[g]);
          const LD r = (LD(v) - breaks_v[h]) / (LD(breaks_v[h + 1]) - breaks_v[h]);
          const Vec3<LD> got = bezier_point(b, g, h, t, r);
          const Vec3<LD> want = surface_point(net, LD(u), LD(v));
          LD err = 0;
          for (int c = 0; c < 3; ++c) err = std::max(err, std::fabs(got[c] - want[c]));
          const double rel = static_cast<double>(err / scale);
          worst.update(rel, [&] {
            return fmt::format("degree {}x{}, u={} v={}", degree_u, degree_v, u, v);
          });
          ASSERT_LE(rel, 1e-16) << "degree " << degree_u << "x" << degree_v << " u=" << u
                                << " v=" << v;
        }
    }
  EXPECT_EQ(surfaces, 54);
}

// The breakpoints and spans recorded with the patches are those of the knot vector.
TEST(BezierDecomposition, PatchIntervalsAreTheNonEmptySpans) {
  Rng rng(7);
  const Surface s = random_surface(rng, 3, 2, 9, 7, Ends::mixed, true);
  const BezierPatches<double> b = decompose_surface(SurfaceNet<double>(s));
  EXPECT_EQ(b.breaks_u, breakpoints(s.knots_u, 3, 9));
  EXPECT_EQ(b.breaks_v, breakpoints(s.knots_v, 2, 7));
  for (int g = 0; g < b.segments_u; ++g) {
    EXPECT_EQ(s.knots_u[b.spans_u[g]], b.breaks_u[g]);
    EXPECT_EQ(s.knots_u[b.spans_u[g] + 1], b.breaks_u[g + 1]);
  }
}

// Curves through decompose_curves directly (one lane).
std::vector<Vec4<double>> decompose_one_curve(int degree, const std::vector<double>& knots,
                                              const std::vector<Vec4<double>>& points,
                                              int expected_segments) {
  const int count = static_cast<int>(points.size());
  std::vector<Vec4<double>> out(static_cast<std::size_t>(expected_segments) * (degree + 1));
  const int segments = decompose_curves<double>(degree, count, knots.data(),
                                                {points.data(), 1, 1, 1}, {out.data(), 1, 1, 1});
  EXPECT_EQ(segments, expected_segments);
  return out;
}

void expect_points(const std::vector<Vec4<double>>& got, const std::vector<Vec4<double>>& want) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t k = 0; k < want.size(); ++k)
    for (int c = 0; c < 4; ++c)
      EXPECT_DOUBLE_EQ(got[k][c], want[k][c]) << "point " << k << " " << c;
}

// Degree 2, knots {0,0,0,1/2,1,1,1}, P0..P3 = (0,0) (1,2) (3,2) (4,0): inserting 1/2 once gives
// alpha_1 = (1/2-0)/(1/2-0) = 1 and alpha_2 = (1/2-0)/(1-0) = 1/2, so Q = P0, P1, (P1+P2)/2, P2,
// P3: segments [P0, P1, (2,2)] and [(2,2), P2, P3].
TEST(BezierDecomposition, HandComputedQuadraticWithOneInteriorKnot) {
  const std::vector<Vec4<double>> p = {{0, 0, 0, 1}, {1, 2, 0, 1}, {3, 2, 0, 1}, {4, 0, 0, 1}};
  expect_points(
      decompose_one_curve(2, {0, 0, 0, 0.5, 1, 1, 1}, p, 2),
      {{0, 0, 0, 1}, {1, 2, 0, 1}, {2, 2, 0, 1}, {2, 2, 0, 1}, {3, 2, 0, 1}, {4, 0, 0, 1}});
}

// The same in homogeneous form with weights 1, 2, 1/2, 1: the inserted point is the homogeneous
// average of w1*P1 = (2,4,0,2) and w2*P2 = (1.5,1,0,0.5): (1.75, 2.5, 0, 1.25).
TEST(BezierDecomposition, HandComputedRationalQuadratic) {
  const std::vector<Vec4<double>> p = {{0, 0, 0, 1}, {2, 4, 0, 2}, {1.5, 1, 0, 0.5}, {4, 0, 0, 1}};
  expect_points(decompose_one_curve(2, {0, 0, 0, 0.5, 1, 1, 1}, p, 2), {{0, 0, 0, 1},
                                                                        {2, 4, 0, 2},
                                                                        {1.75, 2.5, 0, 1.25},
                                                                        {1.75, 2.5, 0, 1.25},
                                                                        {1.5, 1, 0, 0.5},
                                                                        {4, 0, 0, 1}});
}

// Unclamped: the uniform quadratic B-spline on knots 0..5 with three points has the single
// segment [2, 3] whose Bézier points are (P0+P1)/2, P1, (P1+P2)/2 (the classical result).
TEST(BezierDecomposition, HandComputedUniformQuadraticUnclampedBothEnds) {
  const std::vector<Vec4<double>> p = {{0, 0, 0, 1}, {2, 4, 0, 1}, {6, 0, 0, 1}};
  expect_points(decompose_one_curve(2, {0, 1, 2, 3, 4, 5}, p, 1),
                {{1, 2, 0, 1}, {2, 4, 0, 1}, {4, 2, 0, 1}});
}

// Interior knot already at full multiplicity p: no insertion, the segments share the point.
TEST(BezierDecomposition, FullMultiplicityKnotNeedsNoInsertion) {
  const std::vector<Vec4<double>> p = {
      {0, 0, 0, 1}, {1, 1, 0, 1}, {2, 0, 0, 1}, {3, 1, 0, 1}, {4, 0, 0, 1}};
  expect_points(
      decompose_one_curve(2, {0, 0, 0, 1, 1, 2, 2, 2}, p, 2),
      {{0, 0, 0, 1}, {1, 1, 0, 1}, {2, 0, 0, 1}, {2, 0, 0, 1}, {3, 1, 0, 1}, {4, 0, 0, 1}});
}

}  // namespace
}  // namespace nurbs::test
