// The exact trim classification (reference/trim_classify.h) against shapes whose inside is known
// in closed form: the built-in trimmed-plate (rounded rectangle of lines and rational quarter
// circles, minus a rational circle), polygons whose vertices lie on sample rows, nested loops,
// tangent rows, loops closed only within their tolerance.
#include "reference/trim_classify.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "reference/reference_evaluator.h"
#include "reference/trim_crossings.h"
#include "scenes/builtin_scenes.h"
#include "scenes/trimmed_plate.h"
#include "tests/scenes/trimmed_plate_closed_form.h"

namespace nurbs {
namespace {

const TrimmedPlateShape kShape;

struct Analytic {
  bool inside;
  double distance;
};

Analytic analytic_plate(double u, double v) {
  const double signed_distance = test::trimmed_plate_signed_distance(kShape, u, v);
  return {signed_distance < 0, std::fabs(signed_distance)};
}

// The distance's stated accuracy (reference/trim_classify.h): 1e-4 relative below 1e-3 of the
// loops' extent (0.95 here), 1e-2 beyond; plus the double rounding of the points themselves.
double distance_tolerance(double d) {
  return (d < 0.95e-3 ? 1e-4 : 1e-2) * d + 2e-12;
}

SurfaceSamples grid(int n) {
  SurfaceSamples s;
  s.tensor = true;
  s.u = grid_parameters(0, 1, n);
  s.v = grid_parameters(0, 1, n);
  return s;
}

SurfaceSamples explicit_list(const std::vector<Point2>& points) {
  SurfaceSamples s;
  s.tensor = false;
  for (const Point2& p : points) {
    s.u.push_back(p[0]);
    s.v.push_back(p[1]);
  }
  return s;
}

const Trim& plate_trim() {
  static const Scene scene = trimmed_plate_scene();
  return *scene.surfaces[0].trim;
}

class BothScalars : public ::testing::TestWithParam<TrimScalar> {};

// Every sample of a grid whose rows pass through the circle's top and bottom tangents, the
// straight edges and the arcs' end points classifies as the closed form says, away from 1e-12.
TEST_P(BothScalars, PlateGridMatchesClosedFormEverywhereOffTheBoundary) {
  const SurfaceSamples samples = grid(201);  // step 0.005: rows at v = 0.05, 0.2, 0.3, 0.7, 0.95
  const TrimClassification c = classify_trim_samples(plate_trim(), samples, false, GetParam());
  std::size_t compared = 0, wrong = 0;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    const Analytic a = analytic_plate(samples.u_of(k), samples.v_of(k));
    if (a.distance < 1e-12) continue;
    ++compared;
    if ((c.inside[k] == 1) != a.inside) {
      ++wrong;
      ADD_FAILURE() << "(" << samples.u_of(k) << ", " << samples.v_of(k) << ") classified "
                    << int(c.inside[k]);
      if (wrong > 10) break;
    }
  }
  EXPECT_EQ(wrong, 0u);
  EXPECT_GT(compared, 39000u);  // of 40401: only samples on the boundary are left out
}

// Points at known distances d on both sides of the hole's circle, at angles that include the
// circle's control points (tangent rows at 90° and 270°, vertical tangents at 0° and 180°).
TEST_P(BothScalars, PointsAtKnownDistancesFromTheCircleClassifyExactly) {
  std::vector<Point2> points;
  std::vector<bool> expected;
  std::vector<double> distances;
  for (double degrees : {0.0, 17.0, 45.0, 90.0, 135.0, 180.0, 200.0, 270.0, 315.0, 359.0})
    for (double d : {1e-11, 1e-9, 1e-6, 1e-3})
      for (int side : {-1, 1}) {
        const double angle = degrees * std::numbers::pi / 180;
        const double radius = kShape.hole_radius + side * d;
        points.push_back({kShape.hole_center_u + radius * std::cos(angle),
                          kShape.hole_center_v + radius * std::sin(angle)});
        expected.push_back(side > 0);  // outside the hole = inside the face
        distances.push_back(d);
      }
  const TrimClassification c =
      classify_trim_samples(plate_trim(), explicit_list(points), true, GetParam());
  for (std::size_t k = 0; k < points.size(); ++k) {
    EXPECT_EQ(c.inside[k] == 1, expected[k])
        << "(" << points[k][0] << ", " << points[k][1] << ") at distance " << distances[k];
    EXPECT_NEAR(c.distance[k], distances[k], distance_tolerance(distances[k])) << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Trim, BothScalars,
                         ::testing::Values(TrimScalar::f64, TrimScalar::long_double),
                         [](const auto& info) {
                           return info.param == TrimScalar::f64 ? "f64" : "long_double";
                         });

// The convergence test: the inside fraction of an N x N grid tends to the closed-form area
// at the O(1/N) rate of a boundary of finite length (each grid cell the boundary crosses is worth
// at most one cell of area): |fraction - area| <= perimeter * sqrt(2) * h with h = 1/(N-1).
TEST(TrimClassify, InsideFractionConvergesToTheClosedFormArea) {
  const double area = kShape.inside_area();
  const double side = kShape.high - kShape.low, r = kShape.corner_radius;
  const double perimeter =
      4 * (side - 2 * r) + 2 * std::numbers::pi * r + 2 * std::numbers::pi * kShape.hole_radius;
  double previous_error = 1;
  for (int n : {33, 129, 513}) {
    const SurfaceSamples samples = grid(n);
    const TrimClassification c =
        classify_trim_samples(plate_trim(), samples, false, TrimScalar::long_double);
    std::size_t inside = 0;
    for (std::uint8_t flag : c.inside) inside += flag;
    const double fraction = static_cast<double>(inside) / static_cast<double>(samples.count());
    const double error = std::fabs(fraction - area);
    EXPECT_LE(error, perimeter * std::numbers::sqrt2 / (n - 1)) << n;
    EXPECT_LT(error, previous_error) << n;
    previous_error = error;
  }
  // Straight chords instead of the arcs would be off by 4 r^2 (pi/4 - 1/2) ~ 0.026, and the
  // circle's control polygon by far more: both exceed the bound at N = 513 (~0.018).
  EXPECT_LT(previous_error, 4 * r * r * (std::numbers::pi / 4 - 0.5));
}

// The reference evaluator classifies a trimmed scene's samples and measures their distances.
TEST(TrimClassify, ReferenceEvaluatorFillsInsideAndDistance) {
  const Scene scene = *make_builtin_scene("trimmed-plate");
  Sampling sampling;
  sampling.grid_u = sampling.grid_v = 41;
  const std::vector<SurfaceSamples> samples = sample_parameters(scene, sampling);
  const std::vector<ReferenceSurface> reference = evaluate_reference(scene, samples, false);
  ASSERT_EQ(reference[0].inside.size(), samples[0].count());
  ASSERT_EQ(reference[0].trim_distance.size(), samples[0].count());
  for (std::size_t k = 0; k < samples[0].count(); ++k) {
    const Analytic a = analytic_plate(samples[0].u_of(k), samples[0].v_of(k));
    if (a.distance > 1e-12) {
      EXPECT_EQ(reference[0].inside[k] == 1, a.inside) << k;
    }
    EXPECT_NEAR(reference[0].trim_distance[k], a.distance, distance_tolerance(a.distance)) << k;
  }
}

// ---- Polygons: vertices on the sample row, nesting, orientation, gaps --------------------------

TrimCurve segment(Point2 a, Point2 b) {
  return {1, {0, 0, 1, 1}, {a, b}, {1, 1}};
}

TrimLoop polygon(const std::vector<Point2>& corners) {
  TrimLoop loop;
  for (std::size_t k = 0; k < corners.size(); ++k)
    loop.curves.push_back(segment(corners[k], corners[(k + 1) % corners.size()]));
  return loop;
}

std::vector<bool> classify_points(const Trim& trim, const std::vector<Point2>& points,
                                  TrimScalar scalar = TrimScalar::long_double) {
  const TrimClassification c = classify_trim_samples(trim, explicit_list(points), false, scalar);
  return {c.inside.begin(), c.inside.end()};
}

// A diamond's left and right vertices lie on the row v = 0.5; its top and bottom vertices are
// touched by the rows v = 0.9 and v = 0.1. Counting a vertex twice (or not at all) flips whole
// stretches of these rows.
TEST(TrimClassify, VerticesOnTheRowCountOnce) {
  Trim trim;
  trim.loops = {polygon({{0.5, 0.1}, {0.9, 0.5}, {0.5, 0.9}, {0.1, 0.5}})};
  const std::vector<Point2> points = {{0.05, 0.5}, {0.3, 0.5}, {0.7, 0.5}, {0.95, 0.5},
                                      {0.2, 0.9},  {0.8, 0.9}, {0.2, 0.1}, {0.8, 0.1}};
  const std::vector<bool> expected = {false, true, true, false, false, false, false, false};
  EXPECT_EQ(classify_points(trim, points), expected);
  EXPECT_EQ(classify_points(trim, points, TrimScalar::f64), expected);
}

// A horizontal edge lying on the row: the row enters the square at its left side and leaves at
// its right, whatever the edge's direction.
TEST(TrimClassify, EdgesLyingOnTheRow) {
  for (bool reversed : {false, true}) {
    std::vector<Point2> corners = {{0.2, 0.2}, {0.8, 0.2}, {0.8, 0.8}, {0.2, 0.8}};
    if (reversed) std::reverse(corners.begin(), corners.end());
    Trim trim;
    trim.loops = {polygon(corners)};
    // Rows along the bottom and top edges: only the points beyond the square are away from it.
    EXPECT_EQ(classify_points(trim, {{0.1, 0.2}, {0.9, 0.2}, {0.1, 0.8}, {0.9, 0.8}, {0.5, 0.5}}),
              (std::vector<bool>{false, false, false, false, true}))
        << reversed;
  }
}

// Even-odd over nested loops: square in a square in a square (directions mixed).
TEST(TrimClassify, NestedLoopsAlternate) {
  Trim trim;
  trim.loops = {polygon({{0.0, 0.0}, {1.0, 0.0}, {1.0, 1.0}, {0.0, 1.0}}),
                polygon({{0.2, 0.2}, {0.2, 0.8}, {0.8, 0.8}, {0.8, 0.2}}),
                polygon({{0.4, 0.4}, {0.6, 0.4}, {0.6, 0.6}, {0.4, 0.6}})};
  EXPECT_EQ(classify_points(trim, {{0.1, 0.5}, {0.3, 0.5}, {0.5, 0.5}, {0.7, 0.3}}),
            (std::vector<bool>{true, false, true, false}));
}

// A loop closed only within its tolerance: the gap is bridged by its segment, so the row through
// the gap still sees a closed loop.
TEST(TrimClassify, GapsWithinToleranceAreBridged) {
  Trim trim;
  trim.tolerance = 1e-9;
  TrimLoop loop = polygon({{0.2, 0.2}, {0.8, 0.2}, {0.8, 0.8}, {0.2, 0.8}});
  // Move the start of the right edge down by 1e-10, opening a gap at (0.8, 0.2).
  loop.curves[1].points[0] = {0.8, 0.2 - 1e-10};
  loop.curves[3].points[1] = {0.2, 0.2 + 5e-10};  // and another at (0.2, 0.2)
  trim.loops = {loop};
  for (double v : {0.2 - 5e-11, 0.2 + 2e-10, 0.5})
    EXPECT_EQ(classify_points(trim, {{0.1, v}, {0.5, v}, {0.9, v}}),
              (std::vector<bool>{false, v > 0.2 + 1e-10 || v == 0.5, false}))
        << v;
}

// A curve made of several NURBS spans (one cubic B-spline with interior knots, unclamped end
// handled like the surfaces' decomposition) and a rational circle agree with their own dense
// sampling far from the curve.
TEST(TrimClassify, MultiSpanCurveAgreesWithItsDensePolyline) {
  // A closed cubic B-spline "blob": clamped, 8 control points, interior knots, first = last point.
  TrimCurve blob{3,
                 {0, 0, 0, 0, 0.2, 0.45, 0.6, 0.8, 1, 1, 1, 1},
                 {{0.5, 0.1},
                  {0.9, 0.1},
                  {0.95, 0.6},
                  {0.7, 0.95},
                  {0.3, 0.9},
                  {0.05, 0.6},
                  {0.1, 0.1},
                  {0.5, 0.1}},
                 {1, 1, 2, 1, 0.5, 1, 1, 1}};
  Trim trim;
  trim.loops = {TrimLoop{{blob}}};
  // Dense polyline of the curve (evaluated by the reference's own B-spline code would be circular;
  // use a plain de Boor evaluation written here).
  auto evaluate = [&](double t) {
    const int p = 3;
    int span = p;
    while (span < 7 && blob.knots[span + 1] <= t) ++span;
    double d[4][3];
    for (int j = 0; j <= p; ++j) {
      const Point2& q = blob.points[span - p + j];
      const double w = blob.weights[span - p + j];
      d[j][0] = q[0] * w;
      d[j][1] = q[1] * w;
      d[j][2] = w;
    }
    for (int r = 1; r <= p; ++r)
      for (int j = p; j >= r; --j) {
        const int i = span - p + j;
        const double a = (t - blob.knots[i]) / (blob.knots[i + p - r + 1] - blob.knots[i]);
        for (int c = 0; c < 3; ++c) d[j][c] = (1 - a) * d[j - 1][c] + a * d[j][c];
      }
    return Point2{d[p][0] / d[p][2], d[p][1] / d[p][2]};
  };
  std::vector<Point2> polyline;
  for (int k = 0; k <= 20000; ++k) polyline.push_back(evaluate(std::min(k / 20000.0, 1.0 - 1e-16)));
  polyline.back() = blob.points.back();
  auto polyline_inside = [&](double u, double v) {
    bool inside = false;
    for (std::size_t k = 0; k + 1 < polyline.size(); ++k) {
      const Point2 &a = polyline[k], &b = polyline[k + 1];
      if ((a[1] > v) != (b[1] > v) && u < a[0] + (v - a[1]) / (b[1] - a[1]) * (b[0] - a[0]))
        inside = !inside;
    }
    return inside;
  };
  const SurfaceSamples samples = grid(61);
  const TrimClassification c = classify_trim_samples(trim, samples, true, TrimScalar::long_double);
  std::size_t compared = 0, inside = 0;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    if (c.distance[k] < 1e-4) continue;  // the polyline is within ~1e-5 of the curve
    ++compared;
    inside += c.inside[k];
    EXPECT_EQ(c.inside[k] == 1, polyline_inside(samples.u_of(k), samples.v_of(k)))
        << samples.u_of(k) << " " << samples.v_of(k);
  }
  EXPECT_GT(compared, 3000u);
  EXPECT_GT(inside, 1000u);
}

// ---- The fast classifier's entry points (cpu-tensor): Newton refinement, event-free bounds ----

template <typename T>
class FastPath : public ::testing::Test {};
using Scalars = ::testing::Types<double, long double>;
TYPED_TEST_SUITE(FastPath, Scalars);

// The trims of the plate and of every face of the hammer (real CAD: lines, arcs, splines, seams).
template <typename T>
std::vector<TrimPieces<T>> test_trims() {
  std::vector<TrimPieces<T>> trims = {trim_pieces<T>(plate_trim())};
  const Scene hammer = *make_builtin_scene("hammer");
  for (const Surface& s : hammer.surfaces)
    if (s.trim) trims.push_back(trim_pieces<T>(*s.trim));
  return trims;
}

// Newton refinement lands on bisection's root, to within the root's own condition: the forward
// error of a simple root is eps * sum |c_i B_i(t)| / |g'(t)| (one sign variation: a simple root).
TYPED_TEST(FastPath, NewtonRefinementFindsTheBisectionsRoot) {
  using T = TypeParam;
  std::mt19937 random(15);
  std::uniform_real_distribution<double> magnitude(0.01, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 1 + trial % kMaxDegree;
    const int change = 1 + static_cast<int>(random() % n);  // c[0..change) > 0 >= c[change..n]
    T c[kMaxOrder];
    for (int i = 0; i <= n; ++i) c[i] = T(magnitude(random)) * (i < change ? 1 : -1);
    if (trial % 3 == 0 && change < n) c[n] = 0;  // a zero end coefficient: still one variation
    ASSERT_EQ(trim_detail::sign_variations(c, n), 1);
    const T bisected = trim_detail::bisect_single_root(c, n);
    const T newton = trim_detail::newton_single_root(c, n);
    T absolute[kMaxOrder], derivative[kMaxOrder];
    for (int i = 0; i <= n; ++i) absolute[i] = std::fabs(c[i]);
    for (int i = 0; i < n; ++i) derivative[i] = T(n) * (c[i + 1] - c[i]);
    const T slope = std::fabs(trim_detail::bernstein_value(derivative, n - 1, bisected));
    const T condition = trim_detail::bernstein_value(absolute, n, bisected) / slope;
    EXPECT_NEAR(static_cast<double>(newton), static_cast<double>(bisected),
                static_cast<double>(64 * std::numeric_limits<T>::epsilon() * (1 + condition)))
        << "trial " << trial << " degree " << n;
  }
}

// Rows refined by Newton see the events bisection sees, at the same u.
TYPED_TEST(FastPath, NewtonEventsAreBisectionEvents) {
  using T = TypeParam;
  std::vector<T> bisection, newton, scratch;
  std::size_t events = 0;
  for (const TrimPieces<T>& trim : test_trims<T>()) {
    T lo = std::numeric_limits<T>::infinity(), hi = -lo;
    for (const auto& loop : trim.loops)
      for (const TrimPiece<T>& piece : loop)
        for (int i = 0; i <= piece.degree; ++i) {
          lo = std::min(lo, piece.h[i][1] / piece.h[i][2]);
          hi = std::max(hi, piece.h[i][1] / piece.h[i][2]);
        }
    for (int row = 0; row <= 200; ++row) {
      const T v = lo + (hi - lo) * T(row) / T(200);
      bisection.clear();
      newton.clear();
      for (const auto& loop : trim.loops)
        for (std::size_t k = 0; k < loop.size(); ++k) {
          const TrimPiece<T>& next = loop[(k + 1) % loop.size()];
          piece_crossing_events(loop[k], next, v, bisection, scratch, RootRefinement::bisection);
          piece_crossing_events(loop[k], next, v, newton, scratch, RootRefinement::newton);
        }
      ASSERT_EQ(newton.size(), bisection.size()) << "row " << row;
      std::sort(bisection.begin(), bisection.end());
      std::sort(newton.begin(), newton.end());
      for (std::size_t e = 0; e < newton.size(); ++e)
        EXPECT_NEAR(static_cast<double>(newton[e]), static_cast<double>(bisection[e]),
                    1e-9 * static_cast<double>(1 + std::fabs(bisection[e])))
            << "row " << row;
      events += newton.size();
    }
  }
  EXPECT_GT(events, 1000u);
}

// No event from a piece (and its junction to the next) on any line outside its event-free
// bounds, down to the nearest T beyond them; and its curve points lie within them.
TYPED_TEST(FastPath, EventFreeBoundsHoldInT) {
  using T = TypeParam;
  std::vector<T> events, scratch;
  std::size_t pairs = 0;
  for (const TrimPieces<T>& trim : test_trims<T>())
    for (const auto& loop : trim.loops)
      for (std::size_t k = 0; k < loop.size(); ++k) {
        const TrimPiece<T>& piece = loop[k];
        const TrimPiece<T>& next = loop[(k + 1) % loop.size()];
        const auto [lo, hi] = event_free_outside(piece, next);
        const T width = std::max(hi - lo, T(1e-3));
        for (T v : {std::nextafter(lo, -std::numeric_limits<T>::infinity()), lo - width / 7,
                    std::nextafter(hi, std::numeric_limits<T>::infinity()), hi + width / 3}) {
          for (RootRefinement refinement : {RootRefinement::bisection, RootRefinement::newton})
            piece_crossing_events(piece, next, v, events, scratch, refinement);
          EXPECT_TRUE(events.empty()) << "v = " << static_cast<double>(v);
          events.clear();
        }
        for (int s = 0; s <= 8; ++s) {
          T hv[kMaxOrder], w[kMaxOrder];
          for (int i = 0; i <= piece.degree; ++i) {
            hv[i] = piece.h[i][1];
            w[i] = piece.h[i][2];
          }
          const T v = trim_detail::bernstein_value(hv, piece.degree, T(s) / T(8)) /
                      trim_detail::bernstein_value(w, piece.degree, T(s) / T(8));
          EXPECT_TRUE(v >= lo && v <= hi) << static_cast<double>(v);
        }
        ++pairs;
      }
  EXPECT_GT(pairs, 100u);
}

}  // namespace
}  // namespace nurbs
