// The reference evaluator against exact rational arithmetic (GMP). Random rational surfaces of
// degree 1..9 (clamped and unclamped ends, interior knots up to full multiplicity, weights k/8 in
// [1/4, 4], points k/64) are evaluated at the domain ends, at interior knots (right span, the
// reference's convention) and at random doubles; every double converts to a rational exactly, so
// the exact evaluator of exact_nurbs.h sees the very same inputs as the code under test.
//
// Bounds (eps = machine epsilon of the precision under test, L = largest |control coordinate|):
//   points, long double / __float128:                 |error| <= 16 eps L
//   points rounded to double by evaluate_reference:   |error| <= ulp/2 + 16 eps L  (per component)
//   derivatives: |error| <= 16 eps S_kl with the per-sample scale S_kl built from the exact
//   sums B_k = sum_i |N_i^(k)| of the basis derivatives and the weight ratio r = max w / min w:
//   S_10 = r B1u L, S_20 = r (B2u + r B1u^2) L, S_11 = r^2 B1u B1v L (symmetric in v), each
//   at least L;
//   basis functions (degree 1..15, A2.2/A2.3): |N - exact| <= 16 eps, |N^(k) - exact| <= 16 eps
//   B_k.
// The measured worst cases are printed ("[ measured ]") and recorded as test properties.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/reference_evaluator.h"
#include "scenes/builtin_scenes.h"
#include "tests/reference/exact_nurbs.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"

namespace nurbs::test {
namespace {

constexpr double kPointBound = 16;       // in eps * L
constexpr double kDerivativeBound = 16;  // in eps * S_kl
constexpr double kBasisBound = 16;       // in eps (k = 0) or eps * B_k (k = 1, 2)

const long double kEpsLd = std::numeric_limits<long double>::epsilon();

// Parameters of one direction: both ends, up to two interior knots, the double just below one
// interior knot (the left span's piece), three random doubles.
std::vector<double> pick_parameters(Rng& rng, const std::vector<double>& knots, int degree,
                                    int count) {
  const double lo = knots[degree], hi = knots[count];
  std::vector<double> interior;
  for (int k = degree + 1; k < count; ++k)
    if (knots[k] > lo && knots[k] < hi && (interior.empty() || interior.back() != knots[k]))
      interior.push_back(knots[k]);
  std::vector<double> t{lo, hi};
  for (int r = 0; r < 2 && !interior.empty(); ++r)
    t.push_back(interior[uniform_int(rng, 0, static_cast<int>(interior.size()) - 1)]);
  if (!interior.empty())
    t.push_back(
        std::nextafter(interior[uniform_int(rng, 0, static_cast<int>(interior.size()) - 1)], lo));
  for (int r = 0; r < 3; ++r) t.push_back(uniform_real(rng, lo, hi));
  return t;
}

struct ExactCase {
  std::string label;
  Surface surface;
  std::vector<double> u, v;
  std::vector<ExactDerivatives> exact;  // order 2, (a, b) at a * v.size() + b
  std::vector<double> b1u, b2u, b1v, b2v;
  double largest = 0, ratio = 1;
};

ExactCase make_case(std::string label, Surface surface, std::vector<double> u,
                    std::vector<double> v) {
  ExactCase c{
      std::move(label), std::move(surface), std::move(u), std::move(v), {}, {}, {}, {}, {}, 0, 1};
  c.largest = largest_coordinate(c.surface);
  c.ratio = weight_ratio(c.surface);
  const ExactSurface es(c.surface);
  std::vector<ExactBasis> nu, nv;
  for (double t : c.u) {
    nu.push_back(exact_basis_u(es, to_q(t), 2));
    c.b1u.push_back(to_d(abs_sum(nu.back()[1])));
    c.b2u.push_back(to_d(abs_sum(nu.back()[2])));
  }
  for (double t : c.v) {
    nv.push_back(exact_basis_v(es, to_q(t), 2));
    c.b1v.push_back(to_d(abs_sum(nv.back()[1])));
    c.b2v.push_back(to_d(abs_sum(nv.back()[2])));
  }
  for (const ExactBasis& bu : nu)
    for (const ExactBasis& bv : nv) c.exact.push_back(exact_derivatives(es, bu, bv, 2));
  return c;
}

// Four surfaces per degree 1..9 in u (the v degree random 1..9): two clamped, two with mixed
// (clamped or unclamped) ends.
const std::vector<ExactCase>& random_cases() {
  static const std::vector<ExactCase> cases = [] {
    std::vector<ExactCase> out;
    Rng rng(20240601);
    for (int degree_u = 1; degree_u <= 9; ++degree_u)
      for (const Ends ends : {Ends::clamped, Ends::mixed, Ends::clamped, Ends::mixed}) {
        const int degree_v = uniform_int(rng, 1, 9);
        const int count_u = degree_u + 1 + uniform_int(rng, 0, 4);
        const int count_v = degree_v + 1 + uniform_int(rng, 0, 4);
        Surface s = random_surface(rng, degree_u, degree_v, count_u, count_v, ends, true);
        validate_surface(s, 0, "exact_rational_test");
        auto u = pick_parameters(rng, s.knots_u, degree_u, count_u);
        auto v = pick_parameters(rng, s.knots_v, degree_v, count_v);
        std::string label = fmt::format("degree ({},{}) count ({},{}) knots_u [{}] knots_v [{}]",
                                        degree_u, degree_v, count_u, count_v,
                                        fmt::join(s.knots_u, ","), fmt::join(s.knots_v, ","));
        out.push_back(make_case(std::move(label), std::move(s), std::move(u), std::move(v)));
      }
    return out;
  }();
  return cases;
}

std::string at(const ExactCase& c, double u, double v) {
  return fmt::format("u={:.17g} v={:.17g} on {}", u, v, c.label);
}

// ---------------------------------------------------------------------------------------------
// Basis functions and their derivatives (A2.2, A2.3) against the recursive definition.

template <typename T>
void check_basis_against_exact(const char* type, std::uint64_t seed) {
  Rng rng(seed);
  const double eps = static_cast<double>(scalar_epsilon<T>());
  Worst worst0(fmt::format("{}: basis max |N - exact| / eps", type));
  Worst worst12(fmt::format("{}: basis derivatives max |N^(k) - exact| / (eps sum|N^(k)|)", type));
  for (int degree = 1; degree <= kMaxDegree; ++degree)
    for (int trial = 0; trial < 8; ++trial) {
      const int count = degree + 1 + uniform_int(rng, 0, 6);
      const std::vector<double> kd =
          random_knots(rng, degree, count, Ends::mixed, trial % 2 == 0 ? 0.1 : 0.125);
      const std::vector<T> knots(kd.begin(), kd.end());
      std::vector<Q> kq;
      for (double k : kd) kq.push_back(to_q(k));
      for (double u : test_parameters(rng, kd, degree, count, 4)) {
        const ExactBasis exact = exact_basis(kq, degree, count, to_q(u), 2, Side::right);
        const int span = find_span(degree, count, knots.data(), T(u));
        T basis[kMaxOrder];
        T ders[3][kMaxOrder];
        basis_functions(span, T(u), degree, knots.data(), basis);
        basis_function_derivatives(span, T(u), degree, 2, knots.data(), ders);
        auto where = [&] {
          return fmt::format("degree {} u {:.17g} knots [{}]", degree, u, fmt::join(kd, ","));
        };
        // Locality: only N_{span-degree..span} may be non-zero.
        for (int i = 0; i < count; ++i) {
          if (i < span - degree || i > span) {
            ASSERT_EQ(exact[0][i], 0) << "i " << i << " " << where();
          }
        }
        for (int k = 0; k <= 2; ++k) {
          const double scale = k == 0 ? 1.0 : to_d(abs_sum(exact[k]));
          if (scale == 0) {  // derivative order above the degree: exactly zero
            for (int j = 0; j <= degree; ++j) ASSERT_EQ(ders[k][j], T(0)) << where();
            continue;
          }
          for (int j = 0; j <= degree; ++j) {
            const double error =
                to_d(abs_q(to_q(ders[k][j]) - exact[k][span - degree + j])) / (eps * scale);
            if (k == 0) {
              ASSERT_EQ(basis[j], ders[0][j]) << where();
              worst0.update(error, where);
            } else {
              worst12.update(error, where);
            }
            ASSERT_LE(error, kBasisBound) << "N^(" << k << ")[" << j << "] " << where();
          }
        }
      }
    }
}

TEST(ExactRational, BasisFunctionsAndDerivativesLongDouble) {
  check_basis_against_exact<long double>("long double", 31);
}

TEST(ExactRational, BasisFunctionsAndDerivativesFloat128) {
#if NURBSBENCH_HAS_FLOAT128
  check_basis_against_exact<float128>("float128", 32);
#else
  GTEST_SKIP() << "no __float128 in this build";
#endif
}

// ---------------------------------------------------------------------------------------------
// Surface points and derivatives in extended precision (the templates, without rounding).

template <typename T>
void check_points_in(const char* type) {
  const double eps = static_cast<double>(scalar_epsilon<T>());
  Worst worst(fmt::format("{}: surface_point max |error| / (eps L)", type));
  for (const ExactCase& c : random_cases()) {
    const SurfaceNet<T> net(c.surface);
    for (std::size_t a = 0; a < c.u.size(); ++a)
      for (std::size_t b = 0; b < c.v.size(); ++b) {
        const Vec3<T> p = surface_point(net, T(c.u[a]), T(c.v[b]));
        const double error =
            max_abs_error(p, c.exact[a * c.v.size() + b].skl[0][0]) / (eps * c.largest);
        worst.update(error, [&] { return at(c, c.u[a], c.v[b]); });
        ASSERT_LE(error, kPointBound) << at(c, c.u[a], c.v[b]);
      }
  }
}

TEST(ExactRational, SurfacePointLongDouble) {
  check_points_in<long double>("long double");
}

TEST(ExactRational, SurfacePointFloat128) {
#if NURBSBENCH_HAS_FLOAT128
  check_points_in<float128>("float128");
#else
  GTEST_SKIP() << "no __float128 in this build";
#endif
}

template <typename T>
void check_derivatives_in(const char* type) {
  const double eps = static_cast<double>(scalar_epsilon<T>());
  Worst w00(fmt::format("{}: S max |error| / (eps S00)", type));
  Worst w10(fmt::format("{}: Su max |error| / (eps S10)", type));
  Worst w01(fmt::format("{}: Sv max |error| / (eps S01)", type));
  Worst w20(fmt::format("{}: Suu max |error| / (eps S20)", type));
  Worst w11(fmt::format("{}: Suv max |error| / (eps S11)", type));
  Worst w02(fmt::format("{}: Svv max |error| / (eps S02)", type));
  Worst* worst[3][3] = {{&w00, &w01, &w02}, {&w10, &w11, nullptr}, {&w20, nullptr, nullptr}};
  for (const ExactCase& c : random_cases()) {
    const SurfaceNet<T> net(c.surface);
    const double r = c.ratio, L = c.largest;
    for (std::size_t a = 0; a < c.u.size(); ++a)
      for (std::size_t b = 0; b < c.v.size(); ++b) {
        const SurfaceDerivatives<T> d = surface_derivatives(net, T(c.u[a]), T(c.v[b]), 2);
        const double scale[3][3] = {
            {L, r * c.b1v[b] * L, r * (c.b2v[b] + r * c.b1v[b] * c.b1v[b]) * L},
            {r * c.b1u[a] * L, r * r * c.b1u[a] * c.b1v[b] * L, 0},
            {r * (c.b2u[a] + r * c.b1u[a] * c.b1u[a]) * L, 0, 0}};
        for (int k = 0; k <= 2; ++k)
          for (int l = 0; l <= 2 - k; ++l) {
            const double s = std::max(scale[k][l], L);
            const double error =
                max_abs_error(d.skl[k][l], c.exact[a * c.v.size() + b].skl[k][l]) / (eps * s);
            worst[k][l]->update(error, [&] { return at(c, c.u[a], c.v[b]); });
            ASSERT_LE(error, kDerivativeBound)
                << "d^" << k << "/du d^" << l << "/dv at " << at(c, c.u[a], c.v[b]);
          }
      }
  }
}

TEST(ExactRational, SurfaceDerivativesLongDouble) {
  check_derivatives_in<long double>("long double");
}

TEST(ExactRational, SurfaceDerivativesFloat128) {
#if NURBSBENCH_HAS_FLOAT128
  check_derivatives_in<float128>("float128");
#else
  GTEST_SKIP() << "no __float128 in this build";
#endif
}

// ---------------------------------------------------------------------------------------------
// evaluate_reference: both its tensor path (basis rows per parameter) and its explicit-list path,
// rounded to double: within half an ulp of the exact value, plus the extended-precision bound.

void check_evaluate_reference(ReferencePrecision precision, double eps, const char* type) {
  Scene scene{"exact", "random rational surfaces", {}};
  std::vector<SurfaceSamples> tensor, list;
  for (const ExactCase& c : random_cases()) {
    scene.surfaces.push_back(c.surface);
    tensor.push_back(SurfaceSamples{true, c.u, c.v});
    SurfaceSamples pairs{false, {}, {}};
    for (double u : c.u)
      for (double v : c.v) {
        pairs.u.push_back(u);
        pairs.v.push_back(v);
      }
    list.push_back(std::move(pairs));
  }
  validate_scene(scene, "exact_rational_test");
  Worst worst(fmt::format("evaluate_reference({}): max |error| / ulp(exact)", type));
  Worst excess(fmt::format("evaluate_reference({}): max (|error| - ulp/2) / (eps L)", type));
  for (const auto* samples : {&tensor, &list}) {
    const std::vector<ReferenceSurface> ref = evaluate_reference(scene, *samples, false, precision);
    ASSERT_EQ(ref.size(), scene.surfaces.size());
    for (std::size_t i = 0; i < ref.size(); ++i) {
      const ExactCase& c = random_cases()[i];
      ASSERT_EQ(ref[i].positions.size(), c.exact.size());
      for (std::size_t k = 0; k < c.exact.size(); ++k) {
        const double u = (*samples)[i].u_of(k), v = (*samples)[i].v_of(k);
        ASSERT_EQ(u, c.u[k / c.v.size()]);
        ASSERT_EQ(v, c.v[k % c.v.size()]);
        for (int comp = 0; comp < 3; ++comp) {
          const Q& exact = c.exact[k].skl[0][0][comp];
          const double error = to_d(abs_q(to_q(ref[i].positions[k][comp]) - exact));
          const double ulp = double_ulp(exact);
          auto where = [&] { return fmt::format("component {} {}", comp, at(c, u, v)); };
          worst.update(error / ulp, where);
          excess.update((error - 0.5 * ulp) / (eps * c.largest), where);
          ASSERT_LE(error, 0.5 * ulp + kPointBound * eps * c.largest)
              << (samples == &tensor ? "tensor" : "list") << " component " << comp << " "
              << at(c, u, v);
        }
      }
    }
  }
}

TEST(ExactRational, EvaluateReferenceLongDouble) {
  check_evaluate_reference(ReferencePrecision::long_double, static_cast<double>(kEpsLd),
                           "long-double");
}

TEST(ExactRational, EvaluateReferenceFloat128) {
#if NURBSBENCH_HAS_FLOAT128
  check_evaluate_reference(ReferencePrecision::float128, static_cast<double>(FLT128_EPSILON),
                           "float128");
#else
  GTEST_SKIP() << "no __float128 in this build";
#endif
}

// ---------------------------------------------------------------------------------------------
// The built-in scenes the accuracy gates use (non-dyadic data: sqrt(2)/2 weights, 1/3 knots,
// trigonometric points; still exact rationals as doubles), long double points vs exact.
TEST(ExactRational, BuiltinScenesLongDouble) {
  Worst worst("built-in scenes, long double: max |error| / (eps L)");
  for (const char* name :
       {"sphere", "torus", "patch144", "clustered", "creases", "degree-9", "far-origin", "duck"}) {
    const Scene scene = *make_builtin_scene(name);
    const double L = scene.largest_coordinate();
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      const ExactSurface es(s);
      const SurfaceNet<long double> net(s);
      const auto us = grid_parameters(s.u_min(), s.u_max(), 5);
      const auto vs = grid_parameters(s.v_min(), s.v_max(), 5);
      std::vector<ExactBasis> nv;
      for (double v : vs) nv.push_back(exact_basis_v(es, to_q(v), 0));
      for (double u : us) {
        const ExactBasis nu = exact_basis_u(es, to_q(u), 0);
        for (std::size_t b = 0; b < vs.size(); ++b) {
          const QVec3 exact = exact_derivatives(es, nu, nv[b], 0).skl[0][0];
          const double error =
              max_abs_error(surface_point(net, (long double)u, (long double)vs[b]), exact) /
              (static_cast<double>(kEpsLd) * L);
          auto where = [&] {
            return fmt::format("{} surface {} u={:.17g} v={:.17g}", name, s.name, u, vs[b]);
          };
          worst.update(error, where);
          ASSERT_LE(error, kPointBound) << where();
        }
      }
    }
  }
}

}  // namespace
}  // namespace nurbs::test
