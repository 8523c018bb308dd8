// The reference against analytic surfaces: the built-in rational biquadratic sphere and torus lie
// exactly on the sphere/torus (up to the rounding of their sqrt(2)/2 weights to double), so every
// sample of the reference must too, and its normals must be the analytic ones - including at the
// sphere's poles, where Su vanishes and surface_normal's fallback gives the limit. On the real
// models (teapot, duck: collapsed edges) the fallbacks must give finite unit normals everywhere,
// pointing the way the surface's normals next to the collapsed edge point.
//
// Bounds: positions (long-double reference rounded to double) within 1e-15 x radius of the
// analytic surface; normals within 1e-12 rad of the analytic normal; |n| = 1 within 1e-14.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/reference_evaluator.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "tests/reference/test_support.h"

namespace nurbs::test {
namespace {

using LVec = Vec3<long double>;

LVec to_l(const Point3& p) {
  return {p[0], p[1], p[2]};
}

long double length(const LVec& a) {
  return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

// Angle between two vectors, accurate for small angles.
long double angle(const LVec& a, const LVec& b) {
  const LVec c = cross(a, b);
  return std::atan2(length(c), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

struct Evaluated {
  Scene scene;
  std::vector<SurfaceSamples> samples;
  std::vector<ReferenceSurface> reference;
};

Evaluated evaluate_grid(const char* name, int n) {
  Evaluated e{*make_builtin_scene(name), {}, {}};
  Sampling sampling;
  sampling.grid_u = sampling.grid_v = n;
  e.samples = sample_parameters(e.scene, sampling);
  e.reference = evaluate_reference(e.scene, e.samples, true);
  return e;
}

std::string sample_at(const Evaluated& e, std::size_t surface, std::size_t k) {
  return fmt::format("surface {} ({}) u={:.17g} v={:.17g}", surface, e.scene.surfaces[surface].name,
                     e.samples[surface].u_of(k), e.samples[surface].v_of(k));
}

// 101 x 101 samples: the poles (v = 0, 1), the seam (u = 0, 1) and every knot (multiples of 1/4
// in u, 1/2 in v) are grid lines.
TEST(Analytic, SpherePointsAndNormals) {
  const Evaluated e = evaluate_grid("sphere", 101);
  const long double radius = 2;
  Worst on_sphere("sphere: max ||P| - 2| / 2");
  Worst normal_angle("sphere: max angle(n, P/|P|) [rad]");
  Worst unit("sphere: max ||n| - 1|");
  const ReferenceSurface& ref = e.reference[0];
  ASSERT_EQ(ref.positions.size(), 101u * 101u);
  for (std::size_t k = 0; k < ref.positions.size(); ++k) {
    const LVec p = to_l(ref.positions[k]), n = to_l(ref.normals[k]);
    auto where = [&] { return sample_at(e, 0, k); };
    const long double distance = std::fabs(length(p) - radius) / radius;
    on_sphere.update(static_cast<double>(distance), where);
    EXPECT_LE(distance, 1e-15L) << where();
    const long double a = angle(n, p);
    normal_angle.update(static_cast<double>(a), where);
    EXPECT_LE(a, 1e-12L) << where() << " n = (" << n[0] << ", " << n[1] << ", " << n[2] << ")";
    const long double u_error = std::fabs(length(n) - 1);
    unit.update(static_cast<double>(u_error), where);
    EXPECT_LE(u_error, 1e-14L) << where();
  }
  // The poles themselves (where the fallback is needed): exactly the axis, outward.
  const std::size_t nv = e.samples[0].v.size();
  for (std::size_t a = 0; a < e.samples[0].u.size(); ++a) {
    EXPECT_NEAR(ref.normals[a * nv][2], -1.0, 1e-15) << "south pole " << sample_at(e, 0, a * nv);
    EXPECT_NEAR(ref.normals[a * nv + nv - 1][2], 1.0, 1e-15)
        << "north pole " << sample_at(e, 0, a * nv + nv - 1);
  }
}

TEST(Analytic, TorusPointsAndNormals) {
  const Evaluated e = evaluate_grid("torus", 101);
  const long double major = 3, minor = 1;
  Worst on_torus("torus: max |distance to the torus| / r");
  Worst normal_angle("torus: max angle(n, (P - C)/|P - C|) [rad]");
  Worst unit("torus: max ||n| - 1|");
  const ReferenceSurface& ref = e.reference[0];
  for (std::size_t k = 0; k < ref.positions.size(); ++k) {
    const LVec p = to_l(ref.positions[k]), n = to_l(ref.normals[k]);
    auto where = [&] { return sample_at(e, 0, k); };
    const long double rho = std::hypot(p[0], p[1]);
    // (sqrt(x^2 + y^2) - R)^2 + z^2 = r^2, as a distance from the tube's surface
    const long double tube = std::hypot(rho - major, p[2]);
    const long double distance = std::fabs(tube - minor) / minor;
    on_torus.update(static_cast<double>(distance), where);
    EXPECT_LE(distance, 1e-15L) << where();
    const LVec centre{major * p[0] / rho, major * p[1] / rho, 0};
    const LVec expected{p[0] - centre[0], p[1] - centre[1], p[2] - centre[2]};
    const long double a = angle(n, expected);
    normal_angle.update(static_cast<double>(a), where);
    EXPECT_LE(a, 1e-12L) << where();
    const long double u_error = std::fabs(length(n) - 1);
    unit.update(static_cast<double>(u_error), where);
    EXPECT_LE(u_error, 1e-14L) << where();
  }
}

// The same in the reference's own precision (no rounding to double): the distance to the sphere
// is then limited by the weights sqrt(2)/2 stored as doubles (a conic off the circle by ~1e-17).
TEST(Analytic, SphereInLongDouble) {
  const Scene scene = *make_builtin_scene("sphere");
  const SurfaceNet<long double> net(scene.surfaces[0]);
  Worst on_sphere("sphere (long double): max ||P| - 2| / 2");
  for (double u : grid_parameters(0, 1, 41))
    for (double v : grid_parameters(0, 1, 41)) {
      const long double d = std::fabs(length(surface_point<long double>(net, u, v)) - 2) / 2;
      on_sphere.update(static_cast<double>(d), [&] { return fmt::format("u={} v={}", u, v); });
      EXPECT_LE(d, 1e-16L) << "u=" << u << " v=" << v;
    }
}

// Whether surface_normal needs a fallback at (u, v): the same test it applies to Su x Sv.
bool cross_product_resolved(const SurfaceNet<long double>& net, long double u, long double v) {
  const SurfaceDerivatives<long double> d = surface_derivatives(net, u, v, 1);
  Vec3<long double> unused;
  return detail::normalize_if_resolved(cross(d.skl[1][0], d.skl[0][1]), d.skl[1][0], d.skl[0][1],
                                       unused);
}

// Finite unit normals everywhere, never NaN, never the zero vector. Where the fallback is used
// (collapsed edges), the normal must agree with the ordinary normal a little way into the surface
// (the limit it stands for; a wrong sign would be off by pi): within `fallback_tolerance` rad of
// the normal at the sample moved 1e-6 of the way toward the domain centre. (The angle shrinks
// linearly with that step: the duck's head is a cone-like point whose limit normal depends on u.)
void check_model_normals(const char* name, int n, double fallback_tolerance) {
  const Evaluated e = evaluate_grid(name, n);
  Worst unit(fmt::format("{}: max ||n| - 1|", name));
  Worst fallback_angle(
      fmt::format("{}: max angle(fallback normal, normal 1e-6 inside) [rad]", name));
  int fallbacks = 0;
  for (std::size_t i = 0; i < e.scene.surfaces.size(); ++i) {
    const Surface& s = e.scene.surfaces[i];
    const SurfaceNet<long double> net(s);
    const long double mid_u = (s.u_min() + s.u_max()) / 2.0L,
                      mid_v = (s.v_min() + s.v_max()) / 2.0L;
    for (std::size_t k = 0; k < e.reference[i].normals.size(); ++k) {
      const LVec nrm = to_l(e.reference[i].normals[k]);
      auto where = [&] { return sample_at(e, i, k); };
      for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(nrm[c])) << where();
      const long double u_error = std::fabs(length(nrm) - 1);
      unit.update(static_cast<double>(u_error), where);
      ASSERT_LE(u_error, 1e-14L) << where();
      const long double u = e.samples[i].u_of(k), v = e.samples[i].v_of(k);
      if (cross_product_resolved(net, u, v)) continue;
      ++fallbacks;
      const long double step = 1e-6L;
      const LVec inside = surface_normal(net, u + (mid_u - u) * step, v + (mid_v - v) * step);
      const long double a = angle(nrm, inside);
      fallback_angle.update(static_cast<double>(a), where);
      EXPECT_LE(a, fallback_tolerance) << "fallback normal at " << where();
    }
  }
  std::cout << "[ measured ] " << name << ": " << fallbacks << " samples use a fallback normal\n";
  ::testing::Test::RecordProperty(fmt::format("{}_fallback_samples", name), fallbacks);
  EXPECT_GT(fallbacks, 0) << name << " has collapsed edges: the fallback should be exercised";
}

TEST(Analytic, TeapotNormalsFiniteAndUnit) {
  check_model_normals("teapot", 41, 1e-3);
}
TEST(Analytic, DuckNormalsFiniteAndUnit) {
  check_model_normals("duck", 101, 1e-3);
}

// A corner where both tangents vanish (P00 = P10 = P01 of a biquadratic Bezier patch): the
// limit Suv x Sv is zero too, so the last fallback (a sample nudged toward the domain centre)
// must give the normal; it must be the normal the patch has next to that corner.
TEST(Analytic, CornerWithBothTangentsVanishing) {
  Surface s;
  s.name = "corner";
  s.degree_u = s.degree_v = 2;
  s.count_u = s.count_v = 3;
  s.knots_u = s.knots_v = {0, 0, 0, 1, 1, 1};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s.points.push_back({1.0 * i, 1.0 * j, 0.1 * i * j});
  s.points[1] = s.points[3] = s.points[0];  // P01 = P10 = P00
  s.weights.assign(9, 1.0);
  validate_surface(s, 0, "analytic_test");
  const SurfaceNet<long double> net(s);
  const SurfaceDerivatives<long double> d = surface_derivatives(net, 0.0L, 0.0L, 1);
  EXPECT_EQ(length(d.skl[1][0]), 0.0L);
  EXPECT_EQ(length(d.skl[0][1]), 0.0L);
  const LVec n = surface_normal(net, 0.0L, 0.0L);
  for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(n[c]));
  EXPECT_NEAR(static_cast<double>(length(n)), 1.0, 1e-15);
  const LVec inside = surface_normal(net, 1e-3L, 1e-3L);
  const long double a = angle(n, inside);
  std::cout << "[ measured ] corner: angle(fallback normal, normal at (1e-3, 1e-3)) = "
            << static_cast<double>(a) << " rad\n";
  EXPECT_LE(a, 0.05L);
}

// Everything collapsed to a line: no normal exists; the documented answer is the zero vector,
// never NaN.
TEST(Analytic, SurfaceCollapsedToACurveGivesTheZeroVector) {
  Surface s;
  s.name = "line";
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = s.knots_v = {0, 0, 1, 1};
  s.points = {{0, 0, 0}, {0, 0, 0}, {1, 2, 3}, {1, 2, 3}};
  s.weights.assign(4, 1.0);
  const SurfaceNet<long double> net(s);
  for (long double u : {0.0L, 0.5L, 1.0L})
    for (long double v : {0.0L, 0.5L, 1.0L}) {
      const LVec n = surface_normal(net, u, v);
      for (int c = 0; c < 3; ++c) EXPECT_EQ(n[c], 0.0L) << "u=" << u << " v=" << v;
    }
}

}  // namespace
}  // namespace nurbs::test
