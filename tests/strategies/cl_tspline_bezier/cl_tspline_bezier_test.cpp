// cl-tspline-bezier on the OpenCL device (PoCL here: CPU figures), against independent oracles:
// the NURBS reference for the tensor T-spline of a random NURBS surface (tests/tspline: the two
// are the same surface), evaluate_tspline in long double for T-junction meshes, a fresh prepare()
// for update_control_points(), and the reference's normals.
//
// Error bound (positions), derived for unit roundoff u (2^-24 in f32, 2^-53 in f64), L the largest
// |coordinate|, D the control points' bounding-box diagonal, n the most control points active on
// one element, (p, q) the degrees, rho = max w / min w:
// - the decomposition Q_kl = sum_r C[r][kl] w_r (P_r - o), o the element's first point, has
//   non-negative coefficients: |dQ| <= Q_w ((n + 4) u D + 2 u L) (rounding of C, of P and o from
//   double, n products and sums);
// - the Bernstein sums (positive, p + q + 2 terms) add (2p + 2q + 4) u D relative to A_w, the
//   quotient u D, the origin's addition u L;
// - the element-local parameter, (u - u0) / h in double on the host, is rounded once (u
//   relative): the rational patch's derivative is at most p rho 2D per unit of local parameter
//   (Floater's bound), in each direction.
// |error| <= u (3L + D (n + 2p + 2q + 10 + 4 max(p, q) rho)). The measured errors sit far below
// (printed); a wrong element, operator or control point costs O(D).
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "harness/metrics.h"
#include "harness/runner.h"
#include "reference/reference_evaluator.h"
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
using test::tspline_scene;
using test::unit_roundoff;

class cl_tspline_bezier : public ::testing::Test {
 protected:
  void SetUp() override {
    const Availability a = entry().probe();
    if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  }
  static const StrategyEntry& entry() { return *find_strategy("cl-tspline-bezier"); }
};

// The header's bound for a scene of T-splines.
double position_bound(const Scene& scene, Precision precision) {
  double n = 0, pq = 0, pmax = 0, w_min = INFINITY, w_max = 0;
  for (const Surface& s : scene.surfaces) {
    const TSplineInfluence index(*s.tspline, "test");
    for (int cu = 0; cu < index.cells_u(); ++cu)
      for (int cv = 0; cv < index.cells_v(); ++cv)
        n = std::max<double>(n, index.active_end(cu, cv) - index.active_begin(cu, cv));
    pq = std::max<double>(pq, 2 * s.degree_u + 2 * s.degree_v);
    pmax = std::max<double>(pmax, std::max(s.degree_u, s.degree_v));
    for (double w : s.tspline->weights) {
      w_min = std::min(w_min, w);
      w_max = std::max(w_max, w);
    }
  }
  const double rho = w_max / w_min;
  return unit_roundoff(precision) *
         (3 * scene.largest_coordinate() +
          scene.bounding_box_diagonal() * (n + pq + 10 + 4 * pmax * rho));
}

// Span grid with 4 steps (every break and cell interior) and an explicit list of 200 random
// parameters, plus the domain corners.
std::vector<Sampling> test_samplings(Rng& rng, const Scene& scene) {
  return test::span_and_list_samplings(rng, scene, 4, 200);
}

// (1) The tensor T-spline of a random clamped NURBS surface is that surface: the strategy on the
// T-spline agrees with the NURBS reference within the header's bound. Bicubic, 5x3 and 15x15 (the
// kernel's limit), rational (weights 1/4..4). Measured on PoCL: printed per case.
TEST_F(cl_tspline_bezier, TensorTSplinesMatchTheNurbsReference) {
  EXPECT_EQ(entry().capabilities().max_degree, 15);
  Rng rng(41);
  const auto strategy = entry().create(StrategyOptions{});
  struct Case {
    int p, q, cu, cv;
  };
  for (const Case c : {Case{3, 3, 9, 8}, Case{5, 3, 10, 7}, Case{15, 15, 17, 16}}) {
    Scene nurbs;
    nurbs.surfaces.push_back(
        test::random_surface(rng, c.p, c.q, c.cu, c.cv, test::Ends::clamped, true));
    const Scene tspline =
        tspline_scene(infer_tspline(test::tensor_tmesh(nurbs.surfaces[0]), "test"));
    for (const Sampling& sampling : test_samplings(rng, nurbs))
      for (Precision precision : {Precision::f32, Precision::f64}) {
        const EvalResult result =
            evaluate(*strategy, tspline, EvalRequest{sampling, precision, false});
        const auto samples = sample_parameters(nurbs, sampling);
        ASSERT_TRUE(same_samples(result_samples(result), samples));
        const Accuracy acc =
            measure_accuracy(nurbs, result, evaluate_reference(nurbs, samples, false));
        const double bound = position_bound(tspline, precision);
        std::printf("tensor %dx%d %s %s: max_abs %.3g (bound %.3g), max_ulp %.3g\n", c.p, c.q,
                    to_string(precision).data(), sampling.label().c_str(), acc.max_abs, bound,
                    acc.max_ulp);
        EXPECT_EQ(acc.non_finite, 0u);
        EXPECT_LE(acc.max_abs, bound) << c.p << "x" << c.q << " " << to_string(precision);
      }
  }
}

// (2) T-junctions (analysis-suitable random_vertical_tmesh, rational): against the T-spline
// reference (evaluate_tspline in long double), within the header's bound.
TEST_F(cl_tspline_bezier, TJunctionTSplinesMatchTheReference) {
  Rng rng(42);
  const auto strategy = entry().create(StrategyOptions{});
  for (const TMesh& mesh :
       test::random_vertical_tmeshes(rng, {{3, 3}, {5, 3}, {3, 5}, {5, 5}}, 3, true)) {
    const Scene scene = tspline_scene(infer_tspline(mesh, "test"));
    for (const Sampling& sampling : test_samplings(rng, scene))
      for (Precision precision : {Precision::f32, Precision::f64}) {
        const EvalResult result =
            evaluate(*strategy, scene, EvalRequest{sampling, precision, false});
        const Accuracy acc = measure_accuracy(
            scene, result, evaluate_reference(scene, result_samples(result), false));
        const double bound = position_bound(scene, precision);
        std::printf("T-junctions %dx%d %zu points %s %s: max_abs %.3g (bound %.3g), max_ulp %.3g\n",
                    mesh.degree_s, mesh.degree_t, mesh.points.size(), to_string(precision).data(),
                    sampling.label().c_str(), acc.max_abs, bound, acc.max_ulp);
        EXPECT_EQ(acc.non_finite, 0u);
        EXPECT_LE(acc.max_abs, bound);
      }
  }
}

// (3) update_control_points() then evaluate() gives, bit for bit, what a fresh prepare() on the
// moved points gives (the same decomposition kernel on the same points), and differs from the
// frame before (an update that does nothing fails). Another topology is an error. The harness's
// deforming path uses the update ("frame_update"), not prepare.
TEST_F(cl_tspline_bezier, UpdateEqualsAFreshPrepareBitForBit) {
  EXPECT_TRUE(entry().capabilities().updates_control_points);
  Rng rng(43);
  const Scene base =
      tspline_scene(infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 9, 7, true), "test"));
  const auto updated = entry().create(StrategyOptions{});
  const auto fresh = entry().create(StrategyOptions{});
  for (const Sampling& sampling : test_samplings(rng, base))
    for (Precision precision : {Precision::f32, Precision::f64}) {
      test::expect_update_equals_fresh_prepare(*updated, *fresh, base,
                                               EvalRequest{sampling, precision, true});
    }
  const Scene other =
      tspline_scene(infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 9, 7, true), "test"));
  EXPECT_THROW(updated->update_control_points(other), std::invalid_argument);
  EXPECT_THROW(updated->update_control_points(*make_builtin_scene("patch144")),
               std::invalid_argument);

  Sampling grid;
  grid.grid_u = grid.grid_v = 17;
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const Record r =
        measure_deforming(entry(), StrategyOptions{}, base, EvalRequest{grid, precision, false}, 3,
                          ReferencePrecision::long_double);
    ASSERT_EQ(r.status, Status::ok) << r.reason;
    EXPECT_TRUE(r.extra_phases.count("frame_update"));
    EXPECT_FALSE(r.extra_phases.count("frame_prepare"));
    EXPECT_EQ(r.device.details.at("program_builds"), "1");
  }
}

// (4) Normals against evaluate_tspline's (long double), per sample within the angle the header's
// derivative errors allow: with h the element's smallest width, each tangent's error is at most
// dT = u 2 p rho (2L + (n + 2p + 2q + 8) D) / h (the Bernstein derivative weights sum to <= 2p in
// absolute value, on the decomposition's and sums' errors), and the normal's angle at most
// 2 (dT |S_v| + dT |S_u|) / |S_u x S_v| radians (to first order, doubled). Samples where the
// reference has no normal (unresolved) are not scored.
TEST_F(cl_tspline_bezier, NormalsWithinTheDerivedAngle) {
  Rng rng(44);
  const auto strategy = entry().create(StrategyOptions{});
  for (const TMesh& mesh : test::random_vertical_tmeshes(rng, {{3, 3}, {5, 3}}, 2, true)) {
    const Scene scene = tspline_scene(infer_tspline(mesh, "test"));
    const TSplineSurface& t = *scene.surfaces[0].tspline;
    const TSplineInfluence index(t, "test");
    double h = INFINITY;
    for (const auto* breaks : {&index.breaks_u(), &index.breaks_v()})
      for (std::size_t k = 0; k + 1 < breaks->size(); ++k)
        h = std::min(h, (*breaks)[k + 1] - (*breaks)[k]);
    const double rho = *std::max_element(t.weights.begin(), t.weights.end()) /
                       *std::min_element(t.weights.begin(), t.weights.end());
    double n = 0;
    for (int cu = 0; cu < index.cells_u(); ++cu)
      for (int cv = 0; cv < index.cells_v(); ++cv)
        n = std::max<double>(n, index.active_end(cu, cv) - index.active_begin(cu, cv));
    const int p = std::max(t.degree_u, t.degree_v), pq = 2 * t.degree_u + 2 * t.degree_v;
    for (const Sampling& sampling : test_samplings(rng, scene))
      for (Precision precision : {Precision::f32, Precision::f64}) {
        const EvalResult result =
            evaluate(*strategy, scene, EvalRequest{sampling, precision, true});
        const SurfaceResult& r = result.surfaces[0];
        const double dt =
            unit_roundoff(precision) * 2 * p * rho *
            (2 * scene.largest_coordinate() + (n + pq + 8) * scene.bounding_box_diagonal()) / h;
        double worst = 0, worst_ratio = 0;
        std::size_t scored = 0;
        for (std::size_t k = 0; k < r.samples.count(); ++k) {
          const auto ref =
              evaluate_tspline<long double>(t, index, r.samples.u_of(k), r.samples.v_of(k), 1);
          const double su = static_cast<double>(norm(ref.su)),
                       sv = static_cast<double>(norm(ref.sv));
          const double cross_length = static_cast<double>(norm(cross(ref.su, ref.sv)));
          if (norm(ref.normal) == 0) continue;
          ++scored;
          const std::array<double, 3> got = r.normals[k];
          const double dot = got[0] * double(ref.normal[0]) + got[1] * double(ref.normal[1]) +
                             got[2] * double(ref.normal[2]);
          const double cx = got[1] * double(ref.normal[2]) - got[2] * double(ref.normal[1]),
                       cy = got[2] * double(ref.normal[0]) - got[0] * double(ref.normal[2]),
                       cz = got[0] * double(ref.normal[1]) - got[1] * double(ref.normal[0]);
          const double angle = std::atan2(std::hypot(cx, cy, cz), dot);
          const double bound = 2 * (dt * sv + dt * su) / cross_length;
          worst = std::max(worst, angle);
          worst_ratio = std::max(worst_ratio, angle / bound);
          EXPECT_LE(angle, bound) << "sample " << k << " (" << r.samples.u_of(k) << ", "
                                  << r.samples.v_of(k) << ")";
        }
        std::printf(
            "normals %dx%d %s %s: worst %.3g deg, worst angle/bound %.3g, %zu of %zu "
            "scored\n",
            t.degree_u, t.degree_v, to_string(precision).data(), sampling.label().c_str(),
            worst * 180 / M_PI, worst_ratio, scored, r.samples.count());
        EXPECT_GT(scored, r.samples.count() / 2);
      }
  }
}

// (5) T-splines only: a NURBS scene is refused, by the harness's rule and by prepare().
TEST_F(cl_tspline_bezier, NurbsScenesAreRefused) {
  test::expect_nurbs_scenes_refused(entry());
}

// (6) The read-back into the harness's reused result by both paths of
// strategies/opencl/cl_read_back.h (straight into its storage; through pinned staging): both give
// read_back()'s positions and normals bit for bit, a second read-back keeps the storage, and the
// phases' device times and the upload's bytes are recorded.
TEST_F(cl_tspline_bezier, BothReadBackPathsMatchAndReuseTheResult) {
  const Scene scene = *make_builtin_scene("tspline-tjunction");
  Sampling sampling;
  sampling.grid_u = 41;
  sampling.grid_v = 23;
  const EvalRequest request{sampling, Precision::f32, true};
  const auto same = [](const PointArray& a, const PointArray& b) {
    return a.size() == b.size() &&
           std::memcmp(a.data<float>(), b.data<float>(), a.size() * 3 * sizeof(float)) == 0;
  };
  EvalResult expected;
  for (const char* path : {"mapped", "staged"}) {
    SCOPED_TRACE(path);
    StrategyOptions options;
    options.extra["read-back"] = path;
    const auto strategy = entry().create(options);
    strategy->prepare(scene, request);
    strategy->evaluate();
    const EvalResult fresh = strategy->read_back();
    EvalResult reused;
    strategy->read_back_into(reused);
    ASSERT_EQ(reused.surfaces.size(), 1u);
    const float* storage = reused.surfaces[0].positions.data<float>();
    strategy->read_back_into(reused);
    EXPECT_EQ(reused.surfaces[0].positions.data<float>(), storage);
    if (expected.surfaces.empty()) expected = fresh;
    for (const EvalResult* r : {&reused, &expected}) {
      EXPECT_TRUE(same(fresh.surfaces[0].positions, r->surfaces[0].positions));
      EXPECT_TRUE(same(fresh.surfaces[0].normals, r->surfaces[0].normals));
    }
    EXPECT_EQ(fresh.surfaces[0].normals.size(), fresh.surfaces[0].samples.count());
    const DeviceTimes t = strategy->device_times();
    ASSERT_TRUE(t.evaluate_s && t.upload_s && t.read_back_s);
    EXPECT_GT(*t.read_back_s, 0);
    EXPECT_GT(std::stoull(strategy->device().details.at("bytes_uploaded")), 0u);
  }
}

}  // namespace
}  // namespace nurbs
