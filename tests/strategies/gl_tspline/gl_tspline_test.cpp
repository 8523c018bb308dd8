// gl-tspline (001, T-spline evaluation split into passes) against exact oracles:
// - the T-spline of a NURBS surface's tensor mesh is that NURBS surface, so the NURBS reference
//   (long double) is an oracle independent of the T-spline code;
// - on T-meshes with T-junctions, the T-spline reference evaluate_tspline (long double);
// each within the float32 bound derived below, per sample. Also: the passes counted from the
// draws equal ceil(max active points per region / points per pass) + 1 with the maximum found by
// brute force; the finest split (1 point per pass) gives the default's results; NURBS scenes are
// refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <functional>

#include "reference/nurbs_math.h"
#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "scenes/deforming.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/registry.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"
#include "tests/tspline/tspline_meshes.h"

namespace nurbs {
namespace {

using LD = long double;
using test::Rng;

struct Oracle {
  Vec3<LD> point, su, sv, normal;
};
using OracleAt = std::function<Oracle(double, double)>;

struct Evaluated {
  EvalResult result;
  DeviceInfo device;
};

Evaluated run(const Scene& scene, const Sampling& sampling, bool normals, int points_per_pass = 0) {
  StrategyOptions options;
  if (points_per_pass > 0)
    options.extra["tspline-points-per-pass"] = std::to_string(points_per_pass);
  auto strategy = find_strategy("gl-tspline")->create(options);
  strategy->prepare(scene, EvalRequest{sampling, Precision::f32, normals});
  strategy->evaluate();
  return {strategy->read_back(), strategy->device()};
}

Scene tspline_scene(TSplineSurface t) {
  Scene scene;
  scene.name = t.name;
  scene.surfaces.push_back(make_tspline_surface(std::move(t)));
  return scene;
}

Sampling explicit_sampling(const std::vector<double>& us, const std::vector<double>& vs) {
  Sampling s;
  s.mode = SamplingMode::explicit_list;
  s.explicit_uv.emplace_back();
  for (double u : us)
    for (double v : vs) s.explicit_uv.back().push_back({u, v});
  return s;
}

LD length(const Vec3<LD>& a) {
  return norm(a);
}

// The float32 bound of one sample. With B_k the blending functions, A = sum B_k w_k P_k and
// D = sum B_k w_k, every term is a product of non-negative factors, so if each term carries a
// relative error of at most g, |dA| <= g sum B_k w_k |P_k| <= g D M (M = max |P_k|) and
// |dD| <= g D; then |d(A/D)| <= (|dA| + |S| |dD|) / D <= 2 g M (S lies in the hull: |S| <= M).
// g: Cox-de Boor of degree p on float knots and a float parameter costs at most 2 rounding
// errors per level and factor in the two ratio terms, i.e. 2p eps over the p levels (the
// differences t - k are of exact floats, each rounded once); the product N_u N_v and the
// product with P two more; the running sum of n terms n more. The divide one more, and the
// input parameter rounded to float moves the evaluated point by |S_u| |u - float(u)| +
// |S_v| |v - float(v)| (first order). The scene's data here are small dyadics, exact in float.
double sample_bound(int p, int q, int terms, LD max_point, const Oracle& o, double u, double v) {
  const double g = (2.0 * (p + q) + 2 + terms) * FLT_EPSILON;
  const double rounding =
      static_cast<double>(length(o.su)) *
          std::fabs(u - static_cast<double>(static_cast<float>(u))) +
      static_cast<double>(length(o.sv)) * std::fabs(v - static_cast<double>(static_cast<float>(v)));
  return (2 * g + FLT_EPSILON) * static_cast<double>(max_point) + rounding;
}

LD largest_point(const TSplineSurface& t) {
  LD m = 0;
  for (const Point3& p : t.points)
    m = std::max(m, std::sqrt(LD(p[0]) * p[0] + LD(p[1]) * p[1] + LD(p[2]) * p[2]));
  return m;
}

// The most control points whose (open) support covers a cell of the grid of every distinct local
// knot inside the domain, found from the local knot vectors alone (not TSplineInfluence).
int brute_force_max_active(const TSplineSurface& t) {
  auto lines = [](const std::vector<double>& knots, double lo, double hi) {
    std::vector<double> l{lo, hi};
    for (double k : knots)
      if (k > lo && k < hi) l.push_back(k);
    std::sort(l.begin(), l.end());
    l.erase(std::unique(l.begin(), l.end()), l.end());
    return l;
  };
  const std::vector<double> lu = lines(t.knots_u, t.u_min, t.u_max);
  const std::vector<double> lv = lines(t.knots_v, t.v_min, t.v_max);
  int most = 0;
  for (std::size_t a = 0; a + 1 < lu.size(); ++a)
    for (std::size_t b = 0; b + 1 < lv.size(); ++b) {
      const double mu = (lu[a] + lu[a + 1]) / 2, mv = (lv[b] + lv[b + 1]) / 2;
      int count = 0;
      for (std::size_t k = 0; k < t.count(); ++k) {
        const double* ku = t.local_knots_u(k);
        const double* kv = t.local_knots_v(k);
        if (ku[0] < mu && mu < ku[t.degree_u + 1] && kv[0] < mv && mv < kv[t.degree_v + 1]) ++count;
      }
      most = std::max(most, count);
    }
  return most;
}

// Every sample of `r` within its bound of the oracle; normals (where requested and the oracle
// resolves one) within `normal_deg`.
void expect_within_bound(const TSplineSurface& t, const EvalResult& r, const OracleAt& oracle,
                         const std::string& what, test::Worst& worst_ulp, test::Worst& worst_ratio,
                         test::Worst& worst_angle) {
  ASSERT_EQ(r.surfaces.size(), 1u);
  const SurfaceResult& s = r.surfaces[0];
  const int terms = brute_force_max_active(t);
  const LD m = largest_point(t);
  const bool normals = !s.normals.empty();
  for (std::size_t k = 0; k < s.samples.count(); ++k) {
    const double u = s.samples.u_of(k), v = s.samples.v_of(k);
    const Oracle o = oracle(u, v);
    const Point3 p = s.positions[k];
    const double error = std::sqrt(static_cast<double>((p[0] - o.point[0]) * (p[0] - o.point[0]) +
                                                       (p[1] - o.point[1]) * (p[1] - o.point[1]) +
                                                       (p[2] - o.point[2]) * (p[2] - o.point[2])));
    const double bound = sample_bound(t.degree_u, t.degree_v, terms, m, o, u, v);
    const auto where = [&] {
      return fmt::format("{} degree {}x{} (u, v) = ({}, {})", what, t.degree_u, t.degree_v, u, v);
    };
    worst_ulp.update(error / (FLT_EPSILON * static_cast<double>(m)), where);
    worst_ratio.update(error / bound, where);
    ASSERT_LE(error, bound) << where();  // NaN fails
    if (!normals || length(o.normal) == 0) continue;
    const Point3 n = s.normals[k];
    const LD dot = n[0] * o.normal[0] + n[1] * o.normal[1] + n[2] * o.normal[2];
    const double angle =
        static_cast<double>(std::acos(std::clamp(dot, LD(-1), LD(1)))) * 180.0 / M_PI;
    worst_angle.update(angle, where);
    // A quarter of the harness's float32 normal gate (1 degree, strategy_accuracy_test): the
    // measured worst is 0.027 degrees, so a derivative sum off by more than rounding fails.
    ASSERT_LE(angle, 0.25) << where();
  }
}

class GlTSpline : public ::testing::Test {
 protected:
  void SetUp() override {
    const Availability a = gl::Context::probe_any();
    if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  }
};

// (1) Random clamped NURBS surfaces, rational and polynomial, as T-splines of their tensor
// meshes: positions and normals at every knot pair, the ends and random parameters (explicit
// list), and on a grid and a span grid.
TEST_F(GlTSpline, TensorMeshMatchesNurbsReference) {
  Rng rng(41);
  test::Worst ulp("max |S_gl - S_nurbs| / (FLT_EPSILON max |P|)");
  test::Worst ratio("max error / per-sample bound");
  test::Worst angle("max normal angle (deg)");
  struct Degrees {
    int u, v;
  };
  for (const Degrees d : {Degrees{3, 3},
                          {3, 3},
                          {3, 3},
                          {3, 3},
                          {1, 1},
                          {3, 1},
                          {1, 3},
                          {5, 3},
                          {3, 5},
                          {5, 5},
                          {7, 5}})
    for (const bool rational : {false, true}) {
      const int cu = d.u + 1 + test::uniform_int(rng, 0, 5);
      const int cv = d.v + 1 + test::uniform_int(rng, 0, 5);
      const Surface nurbs =
          test::random_surface(rng, d.u, d.v, cu, cv, test::Ends::clamped, rational);
      validate_surface(nurbs, 0, "test");
      TSplineSurface ts = infer_tspline(test::tensor_tmesh(nurbs), "test");
      const SurfaceNet<LD> net(nurbs);
      const OracleAt oracle = [&](double u, double v) {
        const SurfaceDerivatives<LD> n = surface_derivatives(net, LD(u), LD(v), 1);
        return Oracle{n.skl[0][0], n.skl[1][0], n.skl[0][1], surface_normal(net, LD(u), LD(v))};
      };
      const std::string what = rational ? "rational" : "polynomial";
      const Scene scene = tspline_scene(ts);
      const auto us = test::test_parameters(rng, nurbs.knots_u, d.u, cu, 6);
      const auto vs = test::test_parameters(rng, nurbs.knots_v, d.v, cv, 6);
      expect_within_bound(ts, run(scene, explicit_sampling(us, vs), true).result, oracle,
                          what + " explicit", ulp, ratio, angle);
      Sampling grid;
      grid.grid_u = 17;
      grid.grid_v = 13;
      expect_within_bound(ts, run(scene, grid, false).result, oracle, what + " grid", ulp, ratio,
                          angle);
      Sampling span;
      span.mode = SamplingMode::span_grid;
      span.span_steps = 3;
      expect_within_bound(ts, run(scene, span, false).result, oracle, what + " span grid", ulp,
                          ratio, angle);
    }
}

// (2) T-meshes with T-junctions (analysis-suitable), bicubic and mixed degrees, rational and not:
// against the T-spline reference, at every pair of cell breaks (the knot lines, T-junction
// extensions included) and random parameters.
TEST_F(GlTSpline, TJunctionMeshesMatchTSplineReference) {
  Rng rng(42);
  test::Worst ulp("max |S_gl - S_ref| / (FLT_EPSILON max |P|)");
  test::Worst ratio("max error / per-sample bound");
  test::Worst angle("max normal angle (deg)");
  for (const bool rational : {false, true})
    for (const TMesh& mesh :
         test::random_vertical_tmeshes(rng, {{3, 3}, {3, 1}, {5, 3}}, 4, rational)) {
      const TSplineSurface ts = infer_tspline(mesh, "test");
      const TSplineInfluence index(ts, "test");
      const OracleAt oracle = [&](double u, double v) {
        const TSplineEvaluation<LD> e = evaluate_tspline<LD>(ts, index, u, v, 1);
        return Oracle{e.point, e.su, e.sv, e.normal};
      };
      Sampling list;
      list.mode = SamplingMode::explicit_list;
      list.explicit_uv.push_back(
          test::domain_samples(rng, ts, index.breaks_u(), index.breaks_v(), 100));
      expect_within_bound(ts, run(tspline_scene(ts), list, true).result, oracle,
                          rational ? "rational T-mesh" : "polynomial T-mesh", ulp, ratio, angle);
    }
}

// (3) The passes counted from the draws: ceil(max active / points per pass) accumulation passes
// and one divide, the maximum found by brute force over the knot-line cells.
TEST_F(GlTSpline, CountedPassesFollowTheSplit) {
  Rng rng(43);
  const TSplineSurface ts = infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 9, 8, true), "t");
  const int most = brute_force_max_active(ts);
  ASSERT_GE(most, 16);  // bicubic: at least the 16 of a tensor region
  Sampling grid;
  grid.grid_u = 9;
  grid.grid_v = 7;
  for (const int per_pass : {1, 2, 3, 5, 16, 17, 1000}) {
    const Evaluated r = run(tspline_scene(ts), grid, false, per_pass);
    const int accumulation = (most + per_pass - 1) / per_pass;
    EXPECT_EQ(r.device.details.at("passes"), std::to_string(accumulation + 1)) << per_pass;
    EXPECT_EQ(r.device.details.at("max_active_points"), std::to_string(most));
    EXPECT_EQ(r.device.details.at("points_per_pass"), std::to_string(per_pass));
  }
  // The default: 16 points per pass.
  const Evaluated d = run(tspline_scene(ts), grid, false);
  EXPECT_EQ(d.device.details.at("passes"), std::to_string((most + 15) / 16 + 1));
}

// (4) The finest split adds the same terms in the same order, one pass each, through float
// targets that store a float exactly: the default's positions and normals, within the rounding of
// a differently contracted (fused multiply-add) sum, at most one rounding per term of max |P|.
TEST_F(GlTSpline, FinestSplitEqualsDefault) {
  Rng rng(44);
  test::Worst diff("max |S(1 per pass) - S(default)| / (FLT_EPSILON max |P|)");
  for (const bool rational : {false, true}) {
    const TSplineSurface ts =
        infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 10, 9, rational), "t");
    Sampling grid;
    grid.grid_u = 31;
    grid.grid_v = 23;
    const Scene scene = tspline_scene(ts);
    const EvalResult fine = run(scene, grid, true, 1).result;
    const EvalResult coarse = run(scene, grid, true).result;
    const double m = static_cast<double>(largest_point(ts));
    const double bound = brute_force_max_active(ts) * FLT_EPSILON * m;
    const PointArray &a = fine.surfaces[0].positions, &b = coarse.surfaces[0].positions;
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t k = 0; k < a.size(); ++k)
      for (int c = 0; c < 3; ++c) {
        const double e = std::fabs(a[k][c] - b[k][c]);
        diff.update(e / (FLT_EPSILON * m), [&] { return fmt::format("sample {}", k); });
        ASSERT_LE(e, bound) << "sample " << k;
        ASSERT_NEAR(fine.surfaces[0].normals[k][c], coarse.surfaces[0].normals[k][c], 1e-4)
            << "sample " << k;
      }
  }
}

// Deforming frames (003 §2's benchmark): re-uploading the moved points gives exactly what a
// fresh prepare() of the moved scene gives.
TEST_F(GlTSpline, UpdatedPointsEqualAFreshPrepare) {
  Rng rng(46);
  const Scene base =
      tspline_scene(infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 9, 8, true), "t"));
  Sampling grid;
  grid.grid_u = 19;
  grid.grid_v = 11;
  const EvalRequest request{grid, Precision::f32, true};
  auto strategy = find_strategy("gl-tspline")->create(StrategyOptions{});
  ASSERT_TRUE(find_strategy("gl-tspline")->capabilities().updates_control_points);
  strategy->prepare(base, request);
  strategy->evaluate();
  const EvalResult before = strategy->read_back();
  const Scene moved = deformed_scene(base, 7);
  strategy->update_control_points(moved);
  strategy->evaluate();
  const EvalResult updated = strategy->read_back();
  const EvalResult fresh = run(moved, grid, true).result;
  const PointArray &u = updated.surfaces[0].positions, &f = fresh.surfaces[0].positions;
  ASSERT_EQ(u.size(), f.size());
  bool moved_any = false;
  for (std::size_t k = 0; k < u.size(); ++k) {
    ASSERT_EQ(u[k], f[k]) << "sample " << k;
    ASSERT_EQ(updated.surfaces[0].normals[k], fresh.surfaces[0].normals[k]) << "sample " << k;
    moved_any = moved_any || u[k] != before.surfaces[0].positions[k];
  }
  EXPECT_TRUE(moved_any);
  // Another net is not an update.
  const Scene other =
      tspline_scene(infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 5, 5, true), "o"));
  EXPECT_THROW(strategy->update_control_points(other), std::invalid_argument);
}

// (5) NURBS scenes are refused, by the harness's rule and by prepare().
TEST_F(GlTSpline, RefusesNurbsScenes) {
  Rng rng(45);
  Scene scene;
  scene.surfaces.push_back(test::random_surface(rng, 3, 3, 5, 5, test::Ends::clamped, false));
  const StrategyEntry& entry = *find_strategy("gl-tspline");
  const EvalRequest request{Sampling{}, Precision::f32, false};
  const auto reason = refusal_reason(entry.capabilities(), scene, request);
  ASSERT_TRUE(reason.has_value());
  EXPECT_NE(reason->find("T-splines only"), std::string::npos) << *reason;
  auto strategy = entry.create(StrategyOptions{});
  EXPECT_THROW(strategy->prepare(scene, request), RefusedError);
  // And float64, which RGBA32F targets cannot give.
  const Scene t = tspline_scene(infer_tspline(test::tensor_tmesh(scene.surfaces[0]), "t"));
  EXPECT_THROW(strategy->prepare(t, EvalRequest{Sampling{}, Precision::f64, false}), RefusedError);
}

}  // namespace
}  // namespace nurbs
