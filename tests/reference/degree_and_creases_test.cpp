// The reference at the edges of what it accepts: degrees 12..15 (kMaxDegree) against exact
// rational arithmetic, and C0 creases (interior knots of full multiplicity) in the built-in
// "creases" scene: the surface is continuous there, interpolates the control row/column at the
// crease, and its one-sided derivatives (exact left and right limits) differ.
//
// Bounds (eps = long double / __float128 epsilon, L = largest |control coordinate|):
//   degree 12..15 points <= 32 eps L; first derivatives <= 32 eps r B1 L (as in
//   exact_rational_test.cpp); crease continuity and interpolation <= 16 eps L in long double,
//   <= 1e-14 L for the double neighbours of the crease.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/reference_evaluator.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "tests/reference/exact_nurbs.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"

namespace nurbs::test {
namespace {

const double kEpsLd = static_cast<double>(std::numeric_limits<long double>::epsilon());

// ---------------------------------------------------------------------------------------------
// Degrees 12..15.

template <typename T>
void check_high_degree(const char* type, std::uint64_t seed) {
  const double eps = static_cast<double>(scalar_epsilon<T>());
  Rng rng(seed);
  Worst wp(fmt::format("{} degree 12..15: points max |error| / (eps L)", type));
  Worst w1(fmt::format("{} degree 12..15: Su, Sv max |error| / (eps r B1 L)", type));
  for (int degree_u = 12; degree_u <= kMaxDegree; ++degree_u)
    for (const Ends ends : {Ends::clamped, Ends::mixed}) {
      const int degree_v = uniform_int(rng, 12, kMaxDegree);
      Surface s = random_surface(rng, degree_u, degree_v, degree_u + 1 + uniform_int(rng, 0, 3),
                                 degree_v + 1 + uniform_int(rng, 0, 3), ends, true);
      ASSERT_NO_THROW(validate_surface(s, 0, "degree_and_creases_test"));
      const double L = largest_coordinate(s), r = weight_ratio(s);
      const ExactSurface es(s);
      const SurfaceNet<T> net(s);
      const auto us = test_parameters(rng, s.knots_u, s.degree_u, s.count_u, 3);
      const auto vs = test_parameters(rng, s.knots_v, s.degree_v, s.count_v, 3);
      std::vector<ExactBasis> nv;
      for (double v : vs) nv.push_back(exact_basis_v(es, to_q(v), 1));
      for (double u : us) {
        const ExactBasis nu = exact_basis_u(es, to_q(u), 1);
        const double b1u = to_d(abs_sum(nu[1]));
        for (std::size_t b = 0; b < vs.size(); ++b) {
          const ExactDerivatives exact = exact_derivatives(es, nu, nv[b], 1);
          const SurfaceDerivatives<T> d = surface_derivatives(net, T(u), T(vs[b]), 1);
          auto where = [&] {
            return fmt::format("degree ({},{}) u={:.17g} v={:.17g} knots_u [{}] knots_v [{}]",
                               s.degree_u, s.degree_v, u, vs[b], fmt::join(s.knots_u, ","),
                               fmt::join(s.knots_v, ","));
          };
          const double ep =
              max_abs_error(surface_point(net, T(u), T(vs[b])), exact.skl[0][0]) / (eps * L);
          wp.update(ep, where);
          EXPECT_LE(ep, 32) << where();
          const double b1v = to_d(abs_sum(nv[b][1]));
          const double eu = max_abs_error(d.skl[1][0], exact.skl[1][0]) / (eps * r * b1u * L);
          const double ev = max_abs_error(d.skl[0][1], exact.skl[0][1]) / (eps * r * b1v * L);
          w1.update(std::max(eu, ev), where);
          EXPECT_LE(eu, 32) << "Su " << where();
          EXPECT_LE(ev, 32) << "Sv " << where();
        }
      }
    }
}

TEST(HighDegree, LongDoubleAgainstExact) {
  check_high_degree<long double>("long double", 41);
}

TEST(HighDegree, Float128AgainstExact) {
#if NURBSBENCH_HAS_FLOAT128
  check_high_degree<float128>("float128", 42);
#else
  GTEST_SKIP() << "no __float128 in this build";
#endif
}

// evaluate_reference accepts degree 15 and rounds correctly (within half an ulp + 32 eps L).
TEST(HighDegree, EvaluateReferenceDegree15) {
  Rng rng(43);
  Scene scene{"degree15", "", {random_surface(rng, 15, 15, 18, 17, Ends::mixed, true)}};
  validate_scene(scene, "degree_and_creases_test");
  const Surface& s = scene.surfaces[0];
  const ExactSurface es(s);
  Sampling sampling;
  sampling.grid_u = sampling.grid_v = 7;
  const auto samples = sample_parameters(scene, sampling);
  const auto ref = evaluate_reference(scene, samples, true);
  const double L = largest_coordinate(s);
  Worst worst("degree 15 evaluate_reference: max |error| / ulp(exact)");
  for (std::size_t k = 0; k < samples[0].count(); ++k) {
    const double u = samples[0].u_of(k), v = samples[0].v_of(k);
    const QVec3 exact = exact_point(es, to_q(u), to_q(v));
    for (int c = 0; c < 3; ++c) {
      const double error = to_d(abs_q(to_q(ref[0].positions[k][c]) - exact[c]));
      worst.update(error / double_ulp(exact[c]), [&] { return fmt::format("u={} v={}", u, v); });
      EXPECT_LE(error, 0.5 * double_ulp(exact[c]) + 32 * kEpsLd * L) << "u=" << u << " v=" << v;
      EXPECT_TRUE(std::isfinite(ref[0].normals[k][c]));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// C0 creases.

struct Crease {
  double t;   // the knot
  int index;  // the control row/column the surface interpolates there
};

// Interior knots of multiplicity == degree: the basis function N_{k-1} is 1 there, where k is
// the first index of the run.
std::vector<Crease> creases(const std::vector<double>& knots, int degree, int count) {
  std::vector<Crease> out;
  for (int k = degree + 1; k < count;) {
    int m = 1;
    while (k + m < count && knots[k + m] == knots[k]) ++m;
    if (m == degree) out.push_back({knots[k], k - 1});
    k += m;
  }
  return out;
}

// The scene's crease surface transposed (u <-> v), so one set of checks covers both directions.
Surface transposed(const Surface& s) {
  Surface t = s;
  std::swap(t.degree_u, t.degree_v);
  std::swap(t.count_u, t.count_v);
  std::swap(t.knots_u, t.knots_v);
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) {
      t.points[static_cast<std::size_t>(j) * s.count_u + i] = s.point(i, j);
      t.weights[static_cast<std::size_t>(j) * s.count_u + i] = s.weight(i, j);
    }
  return t;
}

// Row i of the net as a curve in v, made a surface of degree 1 in u over two identical rows.
Surface row_curve(const Surface& s, int i) {
  Surface c;
  c.name = fmt::format("row{}", i);
  c.degree_u = 1;
  c.degree_v = s.degree_v;
  c.count_u = 2;
  c.count_v = s.count_v;
  c.knots_u = {0, 0, 1, 1};
  c.knots_v = s.knots_v;
  for (int row = 0; row < 2; ++row)
    for (int j = 0; j < s.count_v; ++j) {
      c.points.push_back(s.point(i, j));
      c.weights.push_back(s.weight(i, j));
    }
  return c;
}

// "crease u=1/3 at v=0.5" for the u direction, "crease v=0.25 at u=0.5" for the transposed one.
std::string crease_at(const char* direction, double crease, double other) {
  return fmt::format("crease {}={:.17g} at {}={:.17g}", direction, crease,
                     std::string_view(direction) == "u" ? "v" : "u", other);
}

const Surface& creases_surface() {
  static const Surface s = make_builtin_scene("creases")->surfaces.at(0);
  return s;
}

void check_crease_continuity(const Surface& s, const char* direction) {
  const std::vector<Crease> cs = creases(s.knots_u, s.degree_u, s.count_u);
  ASSERT_EQ(cs.size(), 2u) << "the creases scene has two full-multiplicity knots per direction";
  const SurfaceNet<long double> net(s);
  const SurfaceNet<double> net_d(s);
  const double L = largest_coordinate(s);
  Worst ld(fmt::format("creases {}: max |left piece - right piece| at the knot / (eps_ld L)",
                       direction));
  Worst dbl(fmt::format("creases {}: max |S(prev double) - S(next double)| / L", direction));
  for (const Crease& c : cs) {
    const long double u = c.t;
    const int right = net.span_u(u);
    const int left = find_span(s.degree_u, s.count_u, net.knots_u.data(),
                               std::nextafter(u, -std::numeric_limits<long double>::infinity()));
    ASSERT_EQ(right, left + s.degree_u) << "the run of " << s.degree_u << " knots separates them";
    long double bu_left[kMaxOrder], bu_right[kMaxOrder], bv[kMaxOrder];
    basis_functions(left, u, s.degree_u, net.knots_u.data(), bu_left);
    basis_functions(right, u, s.degree_u, net.knots_u.data(), bu_right);
    for (double v : grid_parameters(s.v_min(), s.v_max(), 33)) {
      const int sv = net.span_v(v);
      basis_functions(sv, (long double)v, s.degree_v, net.knots_v.data(), bv);
      const auto pl = surface_point_from_basis(net, left, bu_left, sv, bv);
      const auto pr = surface_point_from_basis(net, right, bu_right, sv, bv);
      double e = 0;
      for (int k = 0; k < 3; ++k) e = std::max(e, static_cast<double>(std::fabs(pl[k] - pr[k])));
      auto where = [&] { return crease_at(direction, c.t, v); };
      ld.update(e / (kEpsLd * L), where);
      EXPECT_LE(e, 16 * kEpsLd * L) << where();
      // What a user sampling in double sees on either side of the crease.
      const auto below = surface_point(net_d, std::nextafter(c.t, 0.0), v);
      const auto above = surface_point(net_d, std::nextafter(c.t, 2.0), v);
      const double ed = distance(below, above) / L;
      dbl.update(ed, where);
      EXPECT_LE(ed, 1e-14) << where();
    }
  }
}

TEST(Creases, ContinuousAcrossUCreases) {
  check_crease_continuity(creases_surface(), "u");
}
TEST(Creases, ContinuousAcrossVCreases) {
  check_crease_continuity(transposed(creases_surface()), "v");
}

// S(u_c, v) is the control row's own curve (N_i(u_c) = 1), and at two crossing creases the
// surface passes through the control point.
void check_crease_interpolation(const Surface& s, const char* direction) {
  const SurfaceNet<long double> net(s);
  const double L = largest_coordinate(s);
  Worst worst(fmt::format("creases {}: max |S(u_c, v) - row curve(v)| / (eps_ld L)", direction));
  const auto cs = creases(s.knots_u, s.degree_u, s.count_u);
  ASSERT_FALSE(cs.empty());
  for (const Crease& c : cs) {
    const SurfaceNet<long double> curve(row_curve(s, c.index));
    for (double v : grid_parameters(s.v_min(), s.v_max(), 33)) {
      const auto p = surface_point<long double>(net, c.t, v);
      const auto q = surface_point<long double>(curve, 0.5L, v);
      double e = 0;
      for (int k = 0; k < 3; ++k) e = std::max(e, static_cast<double>(std::fabs(p[k] - q[k])));
      auto where = [&] {
        return fmt::format("{} (row {})", crease_at(direction, c.t, v), c.index);
      };
      worst.update(e / (kEpsLd * L), where);
      EXPECT_LE(e, 16 * kEpsLd * L) << where();
    }
    for (const Crease& d : creases(s.knots_v, s.degree_v, s.count_v)) {
      const auto p = surface_point<long double>(net, c.t, d.t);
      const Point3& expected = s.point(c.index, d.index);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(static_cast<double>(p[k]), expected[k], 16 * kEpsLd * L)
            << "crossing creases (" << c.t << ", " << d.t << ") = P[" << c.index << "][" << d.index
            << "]";
    }
  }
}

TEST(Creases, InterpolatesTheControlRowAtUCreases) {
  check_crease_interpolation(creases_surface(), "u");
}
TEST(Creases, InterpolatesTheControlColumnAtVCreases) {
  check_crease_interpolation(transposed(creases_surface()), "v");
}

// The one-sided derivatives across a crease differ (a kink), and each side is right: the
// reference's derivative at the knot is the exact RIGHT limit (its span convention), its
// derivative at the double just below is the exact LEFT limit (to first order in the ulp).
void check_one_sided_derivatives(const Surface& s, const char* direction) {
  const SurfaceNet<long double> net(s);
  const ExactSurface es(s);
  Worst right_error(
      fmt::format("creases {0}: right S{0} at the knot vs exact, max |error| / |S{0}|", direction));
  Worst left_error(
      fmt::format("creases {0}: S{0} at the double below vs exact left limit, max |error| / |S{0}|",
                  direction));
  Worst jump(fmt::format(
      "creases {0}: min |S{0}_right - S{0}_left| / max(|S{0}_left|, |S{0}_right|)", direction));
  double min_jump = INFINITY;
  for (const Crease& c : creases(s.knots_u, s.degree_u, s.count_u))
    for (double v : grid_parameters(s.v_min(), s.v_max(), 9)) {
      auto where = [&] { return crease_at(direction, c.t, v); };
      const ExactDerivatives exact_right = exact_derivatives(es, to_q(c.t), to_q(v), 1);
      const ExactDerivatives exact_left =
          exact_derivatives(es, to_q(c.t), to_q(v), 1, Side::left, Side::right);
      // Continuity, exactly.
      for (int k = 0; k < 3; ++k) ASSERT_EQ(exact_left.skl[0][0][k], exact_right.skl[0][0][k]);
      Point3 su_left{}, su_right{};
      for (int k = 0; k < 3; ++k) {
        su_left[k] = to_d(exact_left.skl[1][0][k]);
        su_right[k] = to_d(exact_right.skl[1][0][k]);
      }
      const double scale = std::max(std::hypot(su_left[0], su_left[1], su_left[2]),
                                    std::hypot(su_right[0], su_right[1], su_right[2]));
      const double relative_jump = distance(su_left, su_right) / scale;
      min_jump = std::min(min_jump, relative_jump);
      EXPECT_GT(relative_jump, 1e-2) << "no kink at " << where();

      const auto at_knot = surface_derivatives<long double>(net, c.t, v, 1);
      const double er = max_abs_error(at_knot.skl[1][0], exact_right.skl[1][0]) / scale;
      right_error.update(er, where);
      EXPECT_LE(er, 1e-16) << "right limit at " << where();
      const auto below = surface_derivatives<long double>(net, std::nextafter(c.t, 0.0), v, 1);
      const double el = max_abs_error(below.skl[1][0], exact_left.skl[1][0]) / scale;
      left_error.update(el, where);
      EXPECT_LE(el, 1e-12) << "left limit at " << where();
    }
  jump.update(min_jump, [] { return std::string("(minimum over the crease samples)"); });
}

TEST(Creases, OneSidedUDerivativesDiffer) {
  check_one_sided_derivatives(creases_surface(), "u");
}
TEST(Creases, OneSidedVDerivativesDiffer) {
  check_one_sided_derivatives(transposed(creases_surface()), "v");
}

}  // namespace
}  // namespace nurbs::test
