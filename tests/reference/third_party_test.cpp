// The reference against values computed by other people's software (tests/data, see its
// README): OpenCASCADE 7.6.3 Geom_BSplineSurface::D2 on the teapot, the duck and the peers' test
// surfaces at full double precision, and the literal expectations of verb, geomdl, splinepy,
// tinyspline and octave-nurbs at the tolerance each of them used.
//
// OCCT bounds (L = largest |control coordinate| of the surface, D_k = largest |component| of the
// k-th derivative kind over that surface's OCCT rows):
//   points <= 1e-13 L;  Su, Sv <= 1e-11 D_1;  Suu, Svv, Suv <= 1e-9 D_2.
// A derivative is compared only where it is continuous: a k-th derivative in u is skipped at an
// interior knot of multiplicity > degree_u - k (there the two sides differ; OCCT and we may pick
// different sides). The teapot and duck have no such knots, so nothing is skipped on them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/reference_evaluator.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "tests/reference/test_support.h"

namespace nurbs::test {
namespace {

using json = nlohmann::json;
using LDerivs = SurfaceDerivatives<long double>;

Point3 to_point(const json& xyz) {
  // 2-D data (splinepy, tinyspline, verb's curve) live in the plane z = 0.
  return {xyz.at(0).get<double>(), xyz.at(1).get<double>(),
          xyz.size() > 2 ? xyz.at(2).get<double>() : 0.0};
}

Point3 to_point(const Vec3<long double>& p) {
  return {static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])};
}

Surface make_surface(std::string name, int degree_u, int degree_v, std::vector<double> knots_u,
                     std::vector<double> knots_v) {
  Surface s;
  s.name = std::move(name);
  s.degree_u = degree_u;
  s.degree_v = degree_v;
  s.knots_u = std::move(knots_u);
  s.knots_v = std::move(knots_v);
  s.count_u = static_cast<int>(s.knots_u.size()) - degree_u - 1;
  s.count_v = static_cast<int>(s.knots_v.size()) - degree_v - 1;
  return s;
}

// The OCCT files and peer_expected_values' "ctrl"/"weights": [i][j], i = u index, Cartesian.
Surface surface_from_u_major(const std::string& name, const json& j, const char* ctrl_key,
                             const char* weights_key) {
  Surface s = make_surface(name, j.at("degree_u").get<int>(), j.at("degree_v").get<int>(),
                           j.at("knots_u").get<std::vector<double>>(),
                           j.at("knots_v").get<std::vector<double>>());
  const json& ctrl = j.at(ctrl_key);
  for (int i = 0; i < s.count_u; ++i)
    for (int k = 0; k < s.count_v; ++k) {
      s.points.push_back(to_point(ctrl.at(i).at(k)));
      s.weights.push_back(j.contains(weights_key) ? j.at(weights_key).at(i).at(k).get<double>()
                                                  : 1.0);
    }
  validate_surface(s, 0, name);
  return s;
}

// Derivatives in the reference's precision, rounded to double for comparison.
std::array<std::array<Point3, 3>, 3> derivatives_at(const Surface& s, double u, double v) {
  const SurfaceNet<long double> net(s);
  const LDerivs d = surface_derivatives<long double>(net, u, v, 2);
  std::array<std::array<Point3, 3>, 3> out{};
  for (int k = 0; k <= 2; ++k)
    for (int l = 0; l <= 2 - k; ++l) out[k][l] = to_point(d.skl[k][l]);
  return out;
}

double max_component_difference(const Point3& a, const Point3& b) {
  return std::max({std::fabs(a[0] - b[0]), std::fabs(a[1] - b[1]), std::fabs(a[2] - b[2])});
}

// Multiplicity of t among the knots strictly inside the domain (0 for a domain end or no knot).
int interior_multiplicity(const std::vector<double>& knots, int degree, int count, double t) {
  if (t <= knots[degree] || t >= knots[count]) return 0;
  return static_cast<int>(std::count(knots.begin(), knots.end(), t));
}

// ---------------------------------------------------------------------------------------------
// OpenCASCADE evaluations.

struct OcctStats {
  int rows = 0, skipped = 0;
};

// Row layout: u, v, P(3), Su(3), Sv(3), Suu(3), Svv(3), Suv(3).
void check_occt_file(const char* file, const char* label, int* skipped_out = nullptr) {
  const json data = load_test_data(file);
  Worst wp(fmt::format("{} OCCT: points max |error| / L", label));
  Worst w1(fmt::format("{} OCCT: Su, Sv max |error| / D1", label));
  Worst w2(fmt::format("{} OCCT: Suu, Svv, Suv max |error| / D2", label));
  int rows = 0, skipped = 0;
  for (const auto& [name, entry] : data.at("surfaces").items()) {
    const Surface s = surface_from_u_major(name, entry, "ctrl_u_major", "weights_u_major");
    double L = 0, d1 = 0, d2 = 0;
    for (const Point3& p : s.points)
      for (double c : p) L = std::max(L, std::fabs(c));
    for (const json& row : entry.at("evals")) {
      for (int c = 5; c < 11; ++c) d1 = std::max(d1, std::fabs(row.at(c).get<double>()));
      for (int c = 11; c < 20; ++c) d2 = std::max(d2, std::fabs(row.at(c).get<double>()));
    }
    // Explicit-list path of evaluate_reference for the points, surface_derivatives for the rest.
    Scene scene{name, "", {s}};
    SurfaceSamples samples{false, {}, {}};
    for (const json& row : entry.at("evals")) {
      samples.u.push_back(row.at(0).get<double>());
      samples.v.push_back(row.at(1).get<double>());
    }
    const std::vector<ReferenceSurface> ref = evaluate_reference(scene, {samples}, false);
    for (std::size_t r = 0; r < samples.u.size(); ++r) {
      const json& row = entry.at("evals").at(r);
      const double u = samples.u[r], v = samples.v[r];
      auto where = [&] { return fmt::format("{} u={:.17g} v={:.17g}", name, u, v); };
      auto occt = [&](int first) {
        return Point3{row.at(first).get<double>(), row.at(first + 1).get<double>(),
                      row.at(first + 2).get<double>()};
      };
      ++rows;
      const double ep = max_component_difference(ref[0].positions[r], occt(2)) / L;
      wp.update(ep, where);
      EXPECT_LE(ep, 1e-13) << "point at " << where();

      const auto d = derivatives_at(s, u, v);
      const int mu = interior_multiplicity(s.knots_u, s.degree_u, s.count_u, u);
      const int mv = interior_multiplicity(s.knots_v, s.degree_v, s.count_v, v);
      // k-th derivative in a direction is continuous where multiplicity <= degree - k (and
      // everywhere off the interior knots).
      const bool cu1 = mu == 0 || mu <= s.degree_u - 1, cu2 = mu == 0 || mu <= s.degree_u - 2;
      const bool cv1 = mv == 0 || mv <= s.degree_v - 1, cv2 = mv == 0 || mv <= s.degree_v - 2;
      struct Check {
        const char* what;
        int k, l, first;
        bool continuous;
        double scale, tolerance;
        Worst* worst;
      };
      for (const Check& c :
           {Check{"Su", 1, 0, 5, cu1, d1, 1e-11, &w1}, Check{"Sv", 0, 1, 8, cv1, d1, 1e-11, &w1},
            Check{"Suu", 2, 0, 11, cu2, d2, 1e-9, &w2}, Check{"Svv", 0, 2, 14, cv2, d2, 1e-9, &w2},
            Check{"Suv", 1, 1, 17, cu1 && cv1, d2, 1e-9, &w2}}) {
        if (!c.continuous) {
          ++skipped;
          continue;
        }
        const double e = max_component_difference(d[c.k][c.l], occt(c.first)) / c.scale;
        c.worst->update(e, [&] { return fmt::format("{} {}", c.what, where()); });
        EXPECT_LE(e, c.tolerance) << c.what << " at " << where();
      }
    }
  }
  std::cout << "[ measured ] " << label << " OCCT: " << rows << " rows, " << skipped
            << " one-sided derivative comparisons skipped\n";
  EXPECT_GT(rows, 0);
  if (skipped_out) *skipped_out = skipped;
}

TEST(ThirdParty, OcctTeapot) {
  int skipped = -1;
  check_occt_file("teapot_occt.json", "teapot", &skipped);
  EXPECT_EQ(skipped, 0);
}
TEST(ThirdParty, OcctDuck) {
  int skipped = -1;
  check_occt_file("duck_occt.json", "duck", &skipped);
  EXPECT_EQ(skipped, 0);
}
TEST(ThirdParty, OcctPeerSurfaces) {
  check_occt_file("peer_surfaces_occt.json", "peers");
}

// The built-in teapot and duck (scenes/data/*.json, embedded) are the very nets OCCT evaluated.
void check_builtin_equals_occt(const char* scene_name, const char* file) {
  const Scene scene = *make_builtin_scene(scene_name);
  const json data = load_test_data(file);
  ASSERT_EQ(scene.surfaces.size(), data.at("surfaces").size());
  std::size_t i = 0;
  for (const auto& [name, entry] : data.at("surfaces").items()) {
    const Surface occt = surface_from_u_major(name, entry, "ctrl_u_major", "weights_u_major");
    const Surface& ours = scene.surfaces[i++];
    SCOPED_TRACE(fmt::format("{} surface {} vs OCCT {}", scene_name, ours.name, name));
    EXPECT_EQ(ours.name, name);
    EXPECT_EQ(ours.degree_u, occt.degree_u);
    EXPECT_EQ(ours.degree_v, occt.degree_v);
    EXPECT_EQ(ours.count_u, occt.count_u);
    EXPECT_EQ(ours.count_v, occt.count_v);
    EXPECT_EQ(ours.knots_u, occt.knots_u);
    EXPECT_EQ(ours.knots_v, occt.knots_v);
    EXPECT_EQ(ours.points, occt.points);
    EXPECT_EQ(ours.weights, occt.weights);
  }
}

TEST(ThirdParty, BuiltinTeapotIsTheOcctNet) {
  check_builtin_equals_occt("teapot", "teapot_occt.json");
}
TEST(ThirdParty, BuiltinDuckIsTheOcctNet) {
  check_builtin_equals_occt("duck", "duck_occt.json");
}

// ---------------------------------------------------------------------------------------------
// Peers' literal expectations.

const json& peers() {
  static const json data = load_test_data("peer_expected_values.json");
  return data;
}

void expect_near_point(const Point3& got, const Point3& expected, double tol,
                       const std::string& where, Worst& worst) {
  const double e = max_component_difference(got, expected);
  worst.update(e, [&] { return where; });
  EXPECT_LE(e, tol) << where << ": got (" << got[0] << ", " << got[1] << ", " << got[2]
                    << "), expected (" << expected[0] << ", " << expected[1] << ", " << expected[2]
                    << ")";
}

TEST(ThirdParty, VerbQuarterCylinder) {
  const json& p = peers().at("verb_quarter_cylinder_surface");
  const Surface s = surface_from_u_major("verb_quarter_cylinder", p, "ctrl", "weights");
  const double tol = p.at("tol").get<double>();
  Worst worst("verb quarter cylinder max |error|");
  const std::pair<const char*, std::array<int, 2>> keys[] = {{"S", {0, 0}},   {"Su", {1, 0}},
                                                             {"Sv", {0, 1}},  {"Suu", {2, 0}},
                                                             {"Svv", {0, 2}}, {"Suv", {1, 1}}};
  int checked = 0;
  for (const auto& [at, expect] : p.at("expect").items()) {
    double u = 0, v = 0;
    ASSERT_EQ(std::sscanf(at.c_str(), "(%lf,%lf)", &u, &v), 2) << at;
    const auto d = derivatives_at(s, u, v);
    for (const auto& [key, kl] : keys) {
      if (!expect.contains(key)) continue;
      ++checked;
      expect_near_point(d[kl[0]][kl[1]], to_point(expect.at(key)), tol,
                        fmt::format("{} at {}", key, at), worst);
    }
  }
  EXPECT_EQ(checked, 13);
}

// verb's rational quarter circle C(u) as the surface S(u, v) = C(u): degree 1 in v over two
// identical rows, so Sv = Svv = Suv = 0. verb's third derivatives are not checked (the reference
// evaluates up to second order).
TEST(ThirdParty, VerbQuarterCircleAsSurface) {
  const json& p = peers().at("verb_quarter_circle_curve");
  Surface s = make_surface("verb_quarter_circle", p.at("degree").get<int>(), 1,
                           p.at("knots").get<std::vector<double>>(), {0, 0, 1, 1});
  for (std::size_t i = 0; i < p.at("ctrl").size(); ++i)
    for (int row = 0; row < 2; ++row) {
      s.points.push_back(to_point(p.at("ctrl").at(i)));
      s.weights.push_back(p.at("weights").at(i).get<double>());
    }
  validate_surface(s, 0, "verb_quarter_circle");
  const double tol = p.at("tol").get<double>();
  Worst worst("verb quarter circle max |error|");
  for (double v : {0.0, 0.5, 1.0}) {
    const auto d = derivatives_at(s, 0.5, v);
    expect_near_point(d[0][0], to_point(p.at("expect").at("C(0.5)")), tol, "C(0.5)", worst);
    for (const auto& [key, u] : {std::pair{"derivs_at_0", 0.0}, std::pair{"derivs_at_1", 1.0}}) {
      const auto du = derivatives_at(s, u, v);
      for (int k = 0; k <= 2; ++k)
        expect_near_point(du[k][0], to_point(p.at("expect").at(key).at(k)), tol,
                          fmt::format("{}[{}] v={}", key, k, v), worst);
      for (const auto& [k, l] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 1}})
        EXPECT_EQ(du[k][l], (Point3{0, 0, 0})) << "d" << k << l << " at u=" << u << " v=" << v;
    }
  }
}

// geomdl's control net is flattened with v fastest: P[i][j] = flat[i * count_v + j].
Surface geomdl_surface(const json& p) {
  Surface s = make_surface("geomdl_bicubic_6x6", p.at("degree_u").get<int>(),
                           p.at("degree_v").get<int>(), p.at("knots_u").get<std::vector<double>>(),
                           p.at("knots_v").get<std::vector<double>>());
  for (const json& xyz : p.at("ctrl_flat_v_fastest")) s.points.push_back(to_point(xyz));
  s.weights.assign(s.points.size(), 1.0);
  validate_surface(s, 0, s.name);
  return s;
}

// geomdl's expectations are truncated to 3-4 decimals: its tol 1e-3 (absolute) is the tightest
// honest bound (the full-precision values are the OCCT peer rows above).
TEST(ThirdParty, GeomdlBicubic) {
  const json& p = peers().at("geomdl_bicubic_6x6");
  const Surface s = geomdl_surface(p);
  const double tol = p.at("tol").get<double>();
  Worst worst("geomdl bicubic max |error| (values truncated to 1e-3)");
  for (const json& entry : p.at("points")) {
    const double u = entry.at(0).at(0).get<double>(), v = entry.at(0).at(1).get<double>();
    expect_near_point(derivatives_at(s, u, v)[0][0], to_point(entry.at(1)), tol,
                      fmt::format("S({}, {})", u, v), worst);
  }
  int checked = 0;
  for (const auto& [key, skl] : p.at("derivs_geomdl_SKL[k][l]=d^(k+l)S/du^k dv^l").items()) {
    double u = 0, v = 0;
    int order = 0;
    ASSERT_EQ(std::sscanf(key.c_str(), "(%lf,%lf) order%d", &u, &v, &order), 3) << key;
    const auto d = derivatives_at(s, u, v);
    for (int k = 0; k <= order; ++k)
      for (int l = 0; k + l <= order; ++l) {  // k + l > order: geomdl extras, not checked
        ++checked;
        expect_near_point(d[k][l], to_point(skl.at(k).at(l)), tol,
                          fmt::format("SKL[{}][{}] at ({}, {})", k, l, u, v), worst);
      }
  }
  EXPECT_EQ(checked, 3 + 6);
}

// Same net read as homogeneous (w x, w y, w z, w) with w00 = 1/4, w55 = 1/2: the Cartesian
// corners are the stored coordinates divided by w, and a clamped surface interpolates them.
TEST(ThirdParty, GeomdlHomogeneousWeights) {
  const json& p = peers().at("geomdl_nurbs_homogeneous_weights");
  Surface s = geomdl_surface(peers().at("geomdl_bicubic_6x6"));
  s.weights.front() = 0.25;
  s.weights.back() = 0.5;
  for (std::size_t k : {std::size_t{0}, s.points.size() - 1})
    for (double& c : s.points[k]) c /= s.weights[k];
  const double tol = p.at("tol").get<double>();
  Worst worst("geomdl homogeneous weights max |error|");
  expect_near_point(derivatives_at(s, 0, 0)[0][0], to_point(p.at("expect").at("S(0,0)")), tol,
                    "S(0,0)", worst);
  expect_near_point(derivatives_at(s, 1, 1)[0][0], to_point(p.at("expect").at("S(1,1)")), tol,
                    "S(1,1)", worst);
}

// geomdl compares these with ==: they are exact binary fractions, and the long-double reference
// rounded to double reproduces them exactly.
TEST(ThirdParty, GeomdlBiquadraticBezierGridExact) {
  const json& p = peers().at("geomdl_biquadratic_bezier_grid");
  Surface s = make_surface("geomdl_biquadratic", p.at("degree_u").get<int>(),
                           p.at("degree_v").get<int>(), p.at("knots_u").get<std::vector<double>>(),
                           p.at("knots_v").get<std::vector<double>>());
  for (const json& xyz : p.at("ctrl_flat_v_fastest")) s.points.push_back(to_point(xyz));
  s.weights.assign(s.points.size(), 1.0);
  const Scene scene{"geomdl", "", {s}};
  validate_scene(scene, "geomdl_biquadratic");
  const std::vector<double> t{0, 0.25, 0.5, 0.75, 1};
  const auto ref = evaluate_reference(scene, {SurfaceSamples{true, t, t}}, false);
  ASSERT_EQ(ref[0].positions.size(), p.at("values").size());
  for (std::size_t k = 0; k < ref[0].positions.size(); ++k)
    EXPECT_EQ(ref[0].positions[k], to_point(p.at("values").at(k)))
        << "u=" << t[k / 5] << " v=" << t[k % 5];
}

// splinepy flattens control points with u fastest: P[i][j] = flat[j * count_u + i]. Checked as
// numpy.allclose does: |got - expected| <= atol + rtol |expected|, per component.
void check_splinepy(const char* key, bool rational) {
  const json& p = peers().at(key);
  Surface s = make_surface(key, p.at("degree_u").get<int>(), p.at("degree_v").get<int>(),
                           p.at("knots_u").get<std::vector<double>>(),
                           p.at("knots_v").get<std::vector<double>>());
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) {
      const std::size_t flat = static_cast<std::size_t>(j) * s.count_u + i;
      s.points.push_back(to_point(p.at("ctrl_flat_u_fastest").at(flat)));
      s.weights.push_back(rational ? p.at("weights_flat_u_fastest").at(flat).get<double>() : 1.0);
    }
  validate_surface(s, 0, key);
  const double rtol = p.at("rtol").get<double>(), atol = p.at("atol").get<double>();
  Worst worst(fmt::format("{} max |error| / (atol + rtol |expected|)", key));
  for (std::size_t q = 0; q < p.at("queries").size(); ++q) {
    const double u = p.at("queries").at(q).at(0).get<double>();
    const double v = p.at("queries").at(q).at(1).get<double>();
    const auto d = derivatives_at(s, u, v);
    for (const auto& [name, got] : {std::pair{"S", d[0][0]}, std::pair{"Suv", d[1][1]}}) {
      const Point3 expected = to_point(p.at(name).at(q));
      for (int c = 0; c < 3; ++c) {
        const double ratio =
            std::fabs(got[c] - expected[c]) / (atol + rtol * std::fabs(expected[c]));
        worst.update(ratio,
                     [&] { return fmt::format("{} component {} at ({}, {})", name, c, u, v); });
        EXPECT_LE(ratio, 1.0) << name << " component " << c << " at (" << u << ", " << v << ")";
      }
    }
    if (rational) {  // analytic: the quarter annulus between radii 1 and 2, |S(u, v)| = 1 + v
      const double r = std::hypot(d[0][0][0], d[0][0][1]);
      EXPECT_NEAR(r, 1 + v, 1e-15) << "|S| at (" << u << ", " << v << ")";
    }
  }
}

TEST(ThirdParty, SplinepyBspline) {
  check_splinepy("splinepy_bspline_2p2d", false);
}
TEST(ThirdParty, SplinepyQuarterAnnulus) {
  check_splinepy("splinepy_nurbs_2p2d_quarter_annulus", true);
}

// tinyspline's curves as surfaces of degree 1 in v over two identical rows (S(u, v) = C(u));
// tinyspline compares distances with TS_POINT_EPSILON = 1e-5.
Surface curve_as_surface(const std::string& name, int degree, std::vector<double> knots,
                         const json& ctrl) {
  Surface s = make_surface(name, degree, 1, std::move(knots), {0, 0, 1, 1});
  for (const json& xy : ctrl)
    for (int row = 0; row < 2; ++row) s.points.push_back(to_point(xy));
  s.weights.assign(s.points.size(), 1.0);
  validate_surface(s, 0, name);
  return s;
}

TEST(ThirdParty, TinysplineCurves) {
  const json& p = peers().at("tinyspline_curves");
  const double tol = p.at("tol").get<double>();
  Worst worst("tinyspline max distance");
  const json& cubic = p.at("clamped_cubic");
  const Surface c =
      curve_as_surface("tinyspline_cubic", cubic.at("degree").get<int>(),
                       cubic.at("knots").get<std::vector<double>>(), cubic.at("ctrl"));
  for (const auto& [key, u] :
       {std::pair{"C(0.4)", 0.4}, std::pair{"C(0.8)", 0.8}, std::pair{"C(0.75)", 0.75}}) {
    const double e = distance(derivatives_at(c, u, 0.5)[0][0], to_point(cubic.at(key)));
    worst.update(e, [&] { return std::string(key); });
    EXPECT_LE(e, tol) << key;
  }
  const json& quad = p.at("quadratic_10pts");
  for (const auto& [knots_key, key, u] : {std::tuple{"knots_clamped_uniform", "C'(0.8)", 0.8},
                                          std::tuple{"knots_custom", "C'(8.4)", 8.4}}) {
    const Surface q =
        curve_as_surface("tinyspline_quadratic", quad.at("degree").get<int>(),
                         quad.at(knots_key).get<std::vector<double>>(), quad.at("ctrl"));
    const double e = distance(derivatives_at(q, u, 0.5)[1][0], to_point(quad.at(key)));
    worst.update(e, [&] { return std::string(key); });
    EXPECT_LE(e, tol) << key << " with " << knots_key;
  }
}

// octave-nurbs: P[i][j] = (cx[i], cy[j], 0), cx = [0,0,1], cy = [0,0,0,1] on Bezier knots
// reproduces S(u, v) = (u^2, v^3, 0); its tol is 1e-10, we check points to 1e-15 and the
// derivatives (2u, 0, 0), (0, 3v^2, 0), (2, 0, 0), (0, 6v, 0), 0 to 1e-14.
TEST(ThirdParty, OctavePolynomialReproduction) {
  const json& p = peers().at("octave_nurbs_polynomial_reproduction");
  Surface s = make_surface("octave", p.at("degree_u").get<int>(), p.at("degree_v").get<int>(),
                           p.at("knots_u").get<std::vector<double>>(),
                           p.at("knots_v").get<std::vector<double>>());
  const double cx[] = {0, 0, 1}, cy[] = {0, 0, 0, 1};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 4; ++j) s.points.push_back({cx[i], cy[j], 0});
  s.weights.assign(s.points.size(), 1.0);
  validate_surface(s, 0, "octave");
  Worst worst("octave polynomial reproduction max |error|");
  for (int a = 0; a <= 20; ++a)
    for (int b = 0; b <= 20; ++b) {
      const double u = a / 20.0, v = b / 20.0;
      const auto d = derivatives_at(s, u, v);
      const std::string at = fmt::format("({}, {})", u, v);
      expect_near_point(d[0][0], {u * u, v * v * v, 0}, 1e-15, "S" + at, worst);
      expect_near_point(d[1][0], {2 * u, 0, 0}, 1e-14, "Su" + at, worst);
      expect_near_point(d[0][1], {0, 3 * v * v, 0}, 1e-14, "Sv" + at, worst);
      expect_near_point(d[2][0], {2, 0, 0}, 1e-14, "Suu" + at, worst);
      expect_near_point(d[0][2], {0, 6 * v, 0}, 1e-14, "Svv" + at, worst);
      expect_near_point(d[1][1], {0, 0, 0}, 1e-14, "Suv" + at, worst);
    }
}

// OCCT's own conversion tests: a rational sphere of radius 5 satisfies |P| = 5 and a rational
// torus R = 5, r = 2 satisfies (sqrt(x^2 + y^2) - 5)^2 + z^2 = 4, to their tol 1e-10. Our nets are
// the built-in ones mapped affinely: the sphere scaled by 5/2; the torus's profile (radius rho,
// height z) mapped to (5 + 2 (rho - 3), 2 z) in every meridian plane (affine invariance).
TEST(ThirdParty, OcctAnalyticConics) {
  const json& p = peers().at("occt_analytic_conics");
  const double tol = p.at("tol").get<double>();
  Scene sphere = *make_builtin_scene("sphere");
  for (Point3& q : sphere.surfaces[0].points)
    for (double& c : q) c *= 2.5;
  Scene torus = *make_builtin_scene("torus");
  Surface& t = torus.surfaces[0];
  for (int j = 0; j < t.count_v; ++j) {
    const double rho = t.point(0, j)[0];  // row 0 lies in the half-plane y = 0, x = rho >= 2
    const double scale = (5 + 2 * (rho - 3)) / rho;
    for (int i = 0; i < t.count_u; ++i) {
      Point3& q = t.points[static_cast<std::size_t>(i) * t.count_v + j];
      q = {q[0] * scale, q[1] * scale, 2 * q[2]};
    }
  }
  Sampling sampling;
  sampling.grid_u = sampling.grid_v = 51;
  Worst worst("OCCT analytic conics: max |implicit residual|");
  for (const Scene* scene : {&sphere, &torus}) {
    validate_scene(*scene, scene->name);
    const auto samples = sample_parameters(*scene, sampling);
    const auto ref = evaluate_reference(*scene, samples, false);
    for (std::size_t k = 0; k < ref[0].positions.size(); ++k) {
      const Point3& q = ref[0].positions[k];
      const double residual = scene == &sphere
                                  ? std::hypot(q[0], q[1], q[2]) - 5
                                  : std::pow(std::hypot(q[0], q[1]) - 5, 2) + q[2] * q[2] - 4;
      auto where = [&] {
        return fmt::format("{} u={} v={}", scene->name, samples[0].u_of(k), samples[0].v_of(k));
      };
      worst.update(std::fabs(residual), where);
      EXPECT_LE(std::fabs(residual), tol) << where();
    }
  }
}

}  // namespace
}  // namespace nurbs::test
