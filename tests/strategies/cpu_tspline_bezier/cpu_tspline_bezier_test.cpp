// cpu-tspline-bezier against the T-spline reference evaluated independently in the test
// (evaluate_tspline in long double on the point-based form: blending functions on local knot
// vectors, no extraction), a fresh prepare() for update_control_points(), and the reference's
// zero normal where Su x Sv is noise.
//
// Error bound (positions), per coordinate, for unit roundoff u (2^-24 in f32, 2^-53 in f64) and L
// the largest |coordinate| of the control points. The strategy forms each element's homogeneous
// Bézier points about the bounding-box centre o, Q = sum_r C_r w_r (P_r - o, 1), in long double
// (C >= 0, so |Q_c| <= Q_w L: each |P_c - o_c| <= L) and rounds them once (u relative); the
// Bernstein values are rounded once from long double (u relative, 2 directions); the u and v
// contractions are sums of p+1 and q+1 products, gamma_(p+q+2); so numerator and denominator each
// carry at most (p+q+5) u relative to sum B Q_w L and sum B Q_w, the quotient (reciprocal and
// product) 2u, adding o back u: |error| <= (2p + 2q + 13) u L. The parameters enter in double
// and the local parameter is formed in long double: no parameter term. A wrong element, operator
// or control point costs O(size of the surface).
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "scenes/builtin_scenes.h"
#include "scenes/deforming.h"
#include "strategies/registry.h"
#include "tests/reference/random_nurbs.h"
#include "tests/strategies/tspline_strategy_checks.h"
#include "tests/tspline/tspline_meshes.h"

namespace nurbs {
namespace {

using test::evaluate;
using test::Rng;
using test::same_bits;
using test::tspline_scene;
using test::unit_roundoff;

const StrategyEntry& entry() {
  return *find_strategy("cpu-tspline-bezier");
}

// A grid, a span grid (every break and cell interior) and an explicit list of random parameters
// with the domain corners: the row kernels and the per-sample path.
std::vector<Sampling> test_samplings(Rng& rng, const Scene& scene) {
  Sampling grid;
  grid.grid_u = 19;
  grid.grid_v = 23;
  std::vector<Sampling> samplings = test::span_and_list_samplings(rng, scene, 3, 150);
  samplings.insert(samplings.begin(), grid);
  return samplings;
}

// Every sample of every surface against evaluate_tspline<long double>: positions within the
// header's bound; normals (when requested) zero exactly where the reference's are, else within
// `max_angle` radians. Returns the worst position error in units of the bound.
double check_against_reference(const Scene& scene, const EvalResult& result, Precision precision,
                               bool normals, double max_angle) {
  double worst = 0;
  EXPECT_EQ(result.surfaces.size(), scene.surfaces.size());
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const TSplineSurface& t = *scene.surfaces[i].tspline;
    const TSplineInfluence index(t, "test");
    double largest = 0;
    for (const Point3& p : t.points)
      for (double c : p) largest = std::max(largest, std::abs(c));
    const double bound =
        (2 * t.degree_u + 2 * t.degree_v + 13) * unit_roundoff(precision) * largest;
    const SurfaceResult& r = result.surfaces[i];
    for (std::size_t k = 0; k < r.samples.count(); ++k) {
      const double u = r.samples.u_of(k), v = r.samples.v_of(k);
      const auto ref = evaluate_tspline<long double>(t, index, u, v, normals ? 1 : 0);
      const std::array<double, 3> got = r.positions[k];
      for (int c = 0; c < 3; ++c) {
        const double error = std::abs(got[c] - static_cast<double>(ref.point[c]));
        worst = std::max(worst, error / bound);
        EXPECT_LE(error, bound) << "surface " << i << " (" << u << ", " << v << ") coordinate "
                                << c;
      }
      if (!normals) continue;
      const std::array<double, 3> n = r.normals[k];
      if (norm(ref.normal) == 0) {
        EXPECT_EQ(n, (std::array<double, 3>{0, 0, 0})) << "(" << u << ", " << v << ")";
        continue;
      }
      const double dot = n[0] * double(ref.normal[0]) + n[1] * double(ref.normal[1]) +
                         n[2] * double(ref.normal[2]);
      const double cx = n[1] * double(ref.normal[2]) - n[2] * double(ref.normal[1]),
                   cy = n[2] * double(ref.normal[0]) - n[0] * double(ref.normal[2]),
                   cz = n[0] * double(ref.normal[1]) - n[1] * double(ref.normal[0]);
      EXPECT_LE(std::atan2(std::hypot(cx, cy, cz), dot), max_angle) << "(" << u << ", " << v << ")";
    }
  }
  return worst;
}

// Normal angles: a float normal from float derivatives is good to ~1e-3 degrees on these smooth
// surfaces (the accuracy suite allows 1 degree); double to ~1e-12.
double max_angle(Precision precision) {
  return precision == Precision::f32 ? 1e-2 : 1e-10;
}

// (1) Analysis-suitable T-junction meshes (random_vertical_tmesh, rational, degrees 3 and 5 in
// either direction), every sampling, f32 and f64, with and without normals.
TEST(cpu_tspline_bezier, TJunctionTSplinesMatchTheReference) {
  Rng rng(52);
  const auto strategy = entry().create(StrategyOptions{});
  for (const TMesh& mesh :
       test::random_vertical_tmeshes(rng, {{3, 3}, {5, 3}, {3, 5}, {5, 5}}, 2, true)) {
    const Scene scene = tspline_scene(infer_tspline(mesh, "test"));
    for (const Sampling& sampling : test_samplings(rng, scene))
      for (Precision precision : {Precision::f32, Precision::f64})
        for (bool normals : {false, true}) {
          const EvalResult result =
              evaluate(*strategy, scene, EvalRequest{sampling, precision, normals});
          const double worst =
              check_against_reference(scene, result, precision, normals, max_angle(precision));
          std::printf("T-junctions %dx%d %s %s%s: worst %.3g of the bound\n", mesh.degree_s,
                      mesh.degree_t, to_string(precision).data(), sampling.label().c_str(),
                      normals ? " normals" : "", worst);
        }
  }
}

// (2) A real model (tsm-fan: Rhino T-Splines data, several surfaces) at a small grid.
TEST(cpu_tspline_bezier, RealTSplineModelMatchesTheReference) {
  const Scene scene = *make_builtin_scene("tsm-fan");
  const auto strategy = entry().create(StrategyOptions{});
  Sampling grid;
  grid.grid_u = grid.grid_v = 24;
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const EvalResult result = evaluate(*strategy, scene, EvalRequest{grid, precision, true});
    std::printf("tsm-fan %s: worst %.3g of the bound\n", to_string(precision).data(),
                check_against_reference(scene, result, precision, true, max_angle(precision)));
  }
}

// (3) A collapsed edge: the tensor T-spline of a random bicubic NURBS whose first row of control
// points is one point. There Su x Sv vanishes and the T-spline reference has no limit normal
// (zero); the strategy must say zero there too, not cpu-tensor's NURBS limit normal.
TEST(cpu_tspline_bezier, CollapsedEdgeNormalsAreZeroAsInTheReference) {
  Rng rng(53);
  Surface s = test::random_surface(rng, 3, 3, 7, 6, test::Ends::clamped, true);
  for (int j = 1; j < s.count_v; ++j) s.points[j] = s.points[0];
  const Scene scene = tspline_scene(infer_tspline(test::tensor_tmesh(s), "collapsed"));
  const TSplineSurface& t = *scene.surfaces[0].tspline;
  const TSplineInfluence index(t, "test");
  ASSERT_EQ(norm(evaluate_tspline<long double>(t, index, t.u_min, t.v_min, 1).normal), 0)
      << "the edge u = u_min must be collapsed";
  const auto strategy = entry().create(StrategyOptions{});
  Sampling grid;
  grid.grid_u = 9;
  grid.grid_v = 11;
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const EvalResult result = evaluate(*strategy, scene, EvalRequest{grid, precision, true});
    check_against_reference(scene, result, precision, true, max_angle(precision));
    // The u = u_min row is the first: every one of its normals is zero.
    for (int b = 0; b < grid.grid_v; ++b)
      EXPECT_EQ(result.surfaces[0].normals[b], (std::array<double, 3>{0, 0, 0})) << b;
  }
}

// (4) update_control_points() then evaluate() gives, bit for bit, what a fresh prepare() on the
// moved points gives, and differs from the frame before (an update that does nothing fails); a
// new topology is prepared again. One thread and two agree bit for bit (rows are independent).
TEST(cpu_tspline_bezier, UpdateEqualsAFreshPrepareBitForBit) {
  EXPECT_TRUE(entry().capabilities().updates_control_points);
  Rng rng(54);
  const Scene base =
      tspline_scene(infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 9, 7, true), "test"));
  const Scene other =
      tspline_scene(infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 8, 9, true), "test"));
  const auto updated = entry().create(StrategyOptions{});
  const auto fresh = entry().create(StrategyOptions{});
  StrategyOptions one_thread;
  one_thread.threads = 1;
  const auto single = entry().create(one_thread);
  for (const Sampling& sampling : test_samplings(rng, base))
    for (Precision precision : {Precision::f32, Precision::f64}) {
      const EvalRequest request{sampling, precision, true};
      const EvalResult expected =
          test::expect_update_equals_fresh_prepare(*updated, *fresh, base, request);
      const EvalResult one = evaluate(*single, deformed_scene(base, 7), request);
      ASSERT_EQ(expected.surfaces.size(), 1u);
      EXPECT_TRUE(same_bits(one.surfaces[0].positions, expected.surfaces[0].positions));
      if (sampling.mode == SamplingMode::explicit_list) continue;  // its list is base's
      updated->update_control_points(other);
      updated->evaluate();
      const EvalResult switched = updated->read_back();
      EXPECT_TRUE(same_bits(switched.surfaces[0].positions,
                            evaluate(*fresh, other, request).surfaces[0].positions));
    }
}

// (5) T-splines only: a NURBS scene is refused, by the harness's rule and by prepare().
TEST(cpu_tspline_bezier, NurbsScenesAreRefused) {
  test::expect_nurbs_scenes_refused(entry());
}

}  // namespace
}  // namespace nurbs
