// Exact oracles of the T-spline reference (reference/tspline.h, reference/tmesh.h):
// - a T-mesh without T-junctions is a NURBS surface: the T-spline of a NURBS surface's tensor mesh
//   evaluates (point, Su, Sv, normal) to the NURBS reference in long double;
// - the blending functions of analysis-suitable T-meshes sum to one;
// - the influence index (001 Fig 7) selects exactly the functions the O(n) rule finds non-zero.
#include <gtest/gtest.h>

#include <cmath>

#include "reference/nurbs_math.h"
#include "reference/reference_evaluator.h"
#include "reference/sampling.h"
#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"
#include "tests/tspline/tspline_meshes.h"

namespace nurbs {
namespace {

using test::Rng;
using LD = long double;

LD distance(const Vec3<LD>& a, const Vec3<LD>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}
LD length(const Vec3<LD>& a) {
  return norm(a);
}

struct Degrees {
  int u, v;
};

TEST(TSplineNurbs, TensorMeshEqualsNurbsReference) {
  Rng rng(18);
  test::Worst worst_point("max |S_tspline - S_nurbs| / scale");
  test::Worst worst_derivative("max |dS_tspline - dS_nurbs| / (|dS| + scale)");
  for (const Degrees d : {Degrees{1, 1}, {3, 3}, {3, 1}, {1, 3}, {5, 3}, {3, 5}, {5, 5}}) {
    for (int trial = 0; trial < 6; ++trial) {
      const int cu = d.u + 1 + test::uniform_int(rng, 0, 5);
      const int cv = d.v + 1 + test::uniform_int(rng, 0, 5);
      const Surface nurbs =
          test::random_surface(rng, d.u, d.v, cu, cv, test::Ends::clamped, trial % 2 == 1);
      validate_surface(nurbs, 0, "test");
      const TSplineSurface ts = infer_tspline(test::tensor_tmesh(nurbs), "test");
      EXPECT_EQ(ts.u_min, nurbs.u_min());
      EXPECT_EQ(ts.u_max, nurbs.u_max());
      EXPECT_EQ(ts.v_min, nurbs.v_min());
      EXPECT_EQ(ts.v_max, nurbs.v_max());
      // The ray rule must give function (i, j) exactly its knots_u[i .. i+p+1] x knots_v[j ..].
      for (int i = 0; i < cu; ++i)
        for (int j = 0; j < cv; ++j) {
          const std::size_t k = static_cast<std::size_t>(i) * cv + j;
          for (int a = 0; a < d.u + 2; ++a)
            ASSERT_EQ(ts.local_knots_u(k)[a], nurbs.knots_u[i + a]) << "point " << k << " u " << a;
          for (int b = 0; b < d.v + 2; ++b)
            ASSERT_EQ(ts.local_knots_v(k)[b], nurbs.knots_v[j + b]) << "point " << k << " v " << b;
        }
      const TSplineInfluence index(ts, "test");
      const SurfaceNet<LD> net(nurbs);
      Scene scene;
      scene.surfaces.push_back(nurbs);
      const LD scale = scene.largest_coordinate();
      const auto us = test::test_parameters(rng, nurbs.knots_u, d.u, cu, 6);
      const auto vs = test::test_parameters(rng, nurbs.knots_v, d.v, cv, 6);
      for (double u : us)
        for (double v : vs) {
          const auto where = [&] { return fmt::format("degree {}x{} ({}, {})", d.u, d.v, u, v); };
          const TSplineEvaluation<LD> t = evaluate_tspline(ts, index, u, v, 1);
          const SurfaceDerivatives<LD> n = surface_derivatives(net, LD(u), LD(v), 1);
          const LD dp = distance(t.point, n.skl[0][0]) / scale;
          const LD du = distance(t.su, n.skl[1][0]) / (length(n.skl[1][0]) + scale);
          const LD dv = distance(t.sv, n.skl[0][1]) / (length(n.skl[0][1]) + scale);
          worst_point.update(static_cast<double>(dp), where);
          worst_derivative.update(static_cast<double>(std::max(du, dv)), where);
          ASSERT_LE(dp, 1e-15L) << where();
          ASSERT_LE(du, 1e-15L) << where();
          ASSERT_LE(dv, 1e-15L) << where();
          const Vec3<LD> normal = surface_normal(net, LD(u), LD(v));
          // Where Su x Sv resolves, the two normals are the same unit vector.
          if (length(t.normal) > 0) {
            ASSERT_LE(distance(t.normal, normal), 1e-15L) << where();
          }
        }
    }
  }
}

// The sampled reference (what the harness would compare strategies with) is the NURBS one: both
// round long double to double, so they agree to an ulp or two of the coordinates.
TEST(TSplineNurbs, SampledReferenceEqualsTheNurbsReference) {
  Rng rng(42);
  const Surface nurbs = test::random_surface(rng, 3, 3, 8, 7, test::Ends::clamped, true);
  const TSplineSurface ts = infer_tspline(test::tensor_tmesh(nurbs), "test");
  Scene scene;
  scene.surfaces.push_back(nurbs);
  Sampling sampling;
  sampling.grid_u = 33;
  sampling.grid_v = 17;
  const std::vector<SurfaceSamples> samples = sample_parameters(scene, sampling);
  const ReferenceSurface expected = evaluate_reference(scene, samples, true)[0];
  const ReferenceSurface got =
      evaluate_tspline_reference(ts, TSplineInfluence(ts, "test"), samples[0], true);
  ASSERT_EQ(got.positions.size(), expected.positions.size());
  ASSERT_EQ(got.normals.size(), expected.normals.size());
  for (std::size_t k = 0; k < got.positions.size(); ++k) {
    EXPECT_LE(test::distance(got.positions[k], expected.positions[k]), 4e-16 * 8) << k;
    EXPECT_LE(test::distance(got.normals[k], expected.normals[k]), 4e-16) << k;
  }
}

TEST(TSplineNurbs, BlendingFunctionsArePartitionOfUnity) {
  Rng rng(2003);
  test::Worst worst("max |sum of blending functions - 1|");
  for (const TMesh& mesh :
       test::random_vertical_tmeshes(rng, {{3, 3}, {1, 1}, {3, 1}, {5, 3}, {1, 5}}, 8, false)) {
    ASSERT_EQ(analysis_suitability_violation(mesh), "");
    const TSplineSurface ts = infer_tspline(mesh, "test");
    const TSplineInfluence index(ts, "test");
    for (const auto& [u, v] :
         test::domain_samples(rng, ts, index.breaks_u(), index.breaks_v(), 50)) {
      const LD error = std::fabs(tspline_blending_sum(ts, u, v) - 1);
      const auto where = [&] {
        return fmt::format("degree {}x{} ({}, {})", ts.degree_u, ts.degree_v, u, v);
      };
      worst.update(static_cast<double>(error), where);
      ASSERT_LE(error, 64 * scalar_epsilon<LD>()) << where();
    }
  }
}

// A non-AS-safe counterexample guards the test above against passing vacuously: dropping one
// interior vertex's function from an AS mesh must break the partition of unity somewhere.
TEST(TSplineNurbs, PartitionOfUnityCheckDetectsAMissingFunction) {
  Rng rng(7);
  const TMesh mesh = test::random_vertical_tmesh(rng, 3, 3, 7, 7, false);
  TSplineSurface ts = infer_tspline(mesh, "test");
  const std::size_t drop = ts.count() / 2;
  const int pu = ts.degree_u + 2, pv = ts.degree_v + 2;
  const double u = (ts.local_knots_u(drop)[0] + ts.local_knots_u(drop)[pu - 1]) / 2;
  const double v = (ts.local_knots_v(drop)[0] + ts.local_knots_v(drop)[pv - 1]) / 2;
  ts.points.erase(ts.points.begin() + drop);
  ts.weights.erase(ts.weights.begin() + drop);
  ts.knots_u.erase(ts.knots_u.begin() + drop * pu, ts.knots_u.begin() + (drop + 1) * pu);
  ts.knots_v.erase(ts.knots_v.begin() + drop * pv, ts.knots_v.begin() + (drop + 1) * pv);
  EXPECT_GT(std::fabs(tspline_blending_sum(ts, u, v) - 1), 1e-3L);
}

TEST(TSplineNurbs, InfluenceIndexAgreesWithBruteForce) {
  Rng rng(2004);
  test::Worst worst("max |S_index - S_brute| / scale");
  for (const TMesh& mesh : test::random_vertical_tmeshes(rng, {{3, 3}, {1, 3}, {5, 5}}, 6, true)) {
    const TSplineSurface ts = infer_tspline(mesh, "test");
    const TSplineInfluence index(ts, "test");
    for (const auto& [u, v] :
         test::domain_samples(rng, ts, index.breaks_u(), index.breaks_v(), 60)) {
      const auto fast = evaluate_tspline(ts, index, u, v, 0);
      const auto slow = evaluate_tspline_brute_force(ts, u, v, 0);
      const LD error = distance(fast.point, slow.point) / 8;  // points lie in [-8, 8]^3
      worst.update(static_cast<double>(error), [&] { return fmt::format("({}, {})", u, v); });
      ASSERT_LE(error, 64 * scalar_epsilon<LD>()) << "(" << u << ", " << v << ")";
    }
    // Every function listed for a cell is non-zero inside it, every other one zero there.
    for (int cu = 0; cu < index.cells_u(); ++cu)
      for (int cv = 0; cv < index.cells_v(); ++cv) {
        const double u = (index.breaks_u()[cu] + index.breaks_u()[cu + 1]) / 2;
        const double v = (index.breaks_v()[cv] + index.breaks_v()[cv + 1]) / 2;
        std::vector<bool> listed(ts.count(), false);
        for (const int* k = index.active_begin(cu, cv); k != index.active_end(cu, cv); ++k)
          listed[*k] = true;
        for (std::size_t k = 0; k < ts.count(); ++k) {
          const bool nonzero = local_span(ts.degree_u, ts.local_knots_u(k), u, false) >= 0 &&
                               local_span(ts.degree_v, ts.local_knots_v(k), v, false) >= 0;
          ASSERT_EQ(listed[k], nonzero) << "cell " << cu << "," << cv << " point " << k;
        }
      }
  }
}

}  // namespace
}  // namespace nurbs
