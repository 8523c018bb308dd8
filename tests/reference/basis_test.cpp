// Unit tests of the B-spline basis layer of reference/nurbs_math.h: span search (A2.1 with the
// end-of-domain convention), basis functions (A2.2) and their derivatives (A2.3), against The
// NURBS Book's worked example, octave-nurbs' table, and properties that must hold for every valid
// knot vector (partition of unity, non-negativity, derivative rows summing to zero, the span
// invariant knots[s] <= u < knots[s+1]).
#include <gtest/gtest.h>

#include <cfenv>
#include <cfloat>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "reference/nurbs_math.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"

namespace nurbs::test {
namespace {

// Where the reference's convention says u belongs, by a linear scan: the span s in
// [degree, count-1] with knots[s] <= u < knots[s+1]; u >= u_max in the last non-empty span,
// u < u_min in the first.
template <typename T>
int expected_span(const std::vector<T>& knots, int degree, int count, T u) {
  int first = -1, last = -1;
  for (int s = degree; s < count; ++s)
    if (knots[s] < knots[s + 1]) {
      if (first < 0) first = s;
      last = s;
    }
  if (!(u < knots[count])) return last;
  if (u < knots[degree]) return first;
  for (int s = degree; s < count; ++s)
    if (knots[s] <= u && u < knots[s + 1]) return s;
  return -1;
}

template <typename T>
int span_of(const std::vector<T>& knots, int degree, T u) {
  const int count = static_cast<int>(knots.size()) - degree - 1;
  return find_span(degree, count, knots.data(), u);
}

TEST(FindSpan, NurbsBookEx23) {
  const nlohmann::json ex = load_test_data("peer_expected_values.json")["nurbsbook_ex2_3_basis"];
  const auto knots = ex["knots"].get<std::vector<double>>();
  EXPECT_EQ(span_of(knots, ex["degree"].get<int>(), ex["u"].get<double>()), ex["span"].get<int>());
}

// knots {0,0,0,1,2,3,4,4,5,5,5}, degree 2, count 8: spans [2]=[0,1) [3]=[1,2) [4]=[2,3)
// [5]=[3,4) [6] empty [7]=[4,5].
TEST(FindSpan, ExactKnotsBelongToTheSpanTheyStart) {
  const std::vector<double> knots{0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};
  EXPECT_EQ(span_of(knots, 2, 0.0), 2);  // u_min
  EXPECT_EQ(span_of(knots, 2, 1.0), 3);
  EXPECT_EQ(span_of(knots, 2, 2.0), 4);
  EXPECT_EQ(span_of(knots, 2, 3.0), 5);
  EXPECT_EQ(span_of(knots, 2, 4.0), 7);  // double knot: the span after the run, not the empty one
  EXPECT_EQ(span_of(knots, 2, 5.0), 7);  // u_max: last non-empty span
  EXPECT_EQ(span_of(knots, 2, 2.5), 4);
}

TEST(FindSpan, OutsideTheDomainClampsToTheEndSpans) {
  const std::vector<double> knots{0, 0, 0, 1, 2, 3, 4, 4, 5, 5, 5};
  EXPECT_EQ(span_of(knots, 2, -1.0), 2);
  EXPECT_EQ(span_of(knots, 2, -std::numeric_limits<double>::infinity()), 2);
  EXPECT_EQ(span_of(knots, 2, 7.0), 7);
  EXPECT_EQ(span_of(knots, 2, std::numeric_limits<double>::infinity()), 7);
}

// Domain ends with repeated knots just inside (unclamped knot vectors): the end parameter must
// still land in a NON-EMPTY span of the domain.
TEST(FindSpan, DomainEndsNextToRepeatedKnots) {
  // degree 2, count 5: domain [knots[2], knots[5]] = [0, 2]; knots[4] = knots[5] = 2, so span 4
  // is empty and u_max = 2 belongs to span 3 = [1, 2].
  const std::vector<double> end_run{0, 0, 0, 1, 2, 2, 3, 4};
  EXPECT_EQ(span_of(end_run, 2, 2.0), 3);
  EXPECT_EQ(span_of(end_run, 2, std::nextafter(2.0, 0.0)), 3);
  EXPECT_EQ(span_of(end_run, 2, 1.0), 3);
  // degree 2, count 5: domain [knots[2], knots[5]] = [0, 2]; knots[2] = knots[3] = 0, so span 2
  // is empty and u_min = 0 belongs to span 3 = [0, 1).
  const std::vector<double> start_run{-2, -1, 0, 0, 1, 2, 3, 3};
  EXPECT_EQ(span_of(start_run, 2, 0.0), 3);
  EXPECT_EQ(span_of(start_run, 2, -0.5), 3);
  EXPECT_EQ(span_of(start_run, 2, 2.0), 4);
  // degree 3, full-multiplicity interior knots right after the start and before the end.
  const std::vector<double> inner_runs{0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 3};
  EXPECT_EQ(span_of(inner_runs, 3, 0.0), 3);
  EXPECT_EQ(span_of(inner_runs, 3, 1.0), 6);
  EXPECT_EQ(span_of(inner_runs, 3, 2.0), 9);
  EXPECT_EQ(span_of(inner_runs, 3, 3.0), 9);
  EXPECT_EQ(span_of(inner_runs, 3, std::nextafter(1.0, 0.0)), 3);
  EXPECT_EQ(span_of(inner_runs, 3, std::nextafter(2.0, 0.0)), 6);
}

// No epsilon: the neighbours of a knot in floating point fall on their own side of it.
template <typename T>
void check_next_to_knots(const std::vector<T>& knots, int degree) {
  const int count = static_cast<int>(knots.size()) - degree - 1;
  const T lo = knots[degree], hi = knots[count];
  for (int k = degree; k <= count; ++k) {
    const T knot = knots[k];
    for (T u : {std::nextafter(knot, -std::numeric_limits<T>::infinity()), knot,
                std::nextafter(knot, std::numeric_limits<T>::infinity())}) {
      const int s = find_span(degree, count, knots.data(), u);
      ASSERT_EQ(s, expected_span(knots, degree, count, u)) << "u = " << u << " (knot " << k << ")";
      ASSERT_GE(s, degree);
      ASSERT_LT(s, count);
      ASSERT_LT(knots[s], knots[s + 1]) << "empty span selected at u = " << u;
      if (u >= lo && u < hi) {
        ASSERT_LE(knots[s], u);
        ASSERT_LT(u, knots[s + 1]);
      }
    }
  }
}

TEST(FindSpan, NeighboursOfKnotsDouble) {
  // 0.1, 0.3, 0.7 are not binary fractions: the knot as stored is what u is compared with.
  check_next_to_knots<double>({0, 0, 0, 0.1, 0.3, 0.3, 0.7, 1, 1, 1}, 2);
  check_next_to_knots<double>({-1e-300, 0, 1e-300, 1e-300, 2e-300, 3e-300, 4e-300}, 2);
}

TEST(FindSpan, NeighboursOfKnotsFloat) {
  check_next_to_knots<float>({0, 0, 0, 0.1f, 0.3f, 0.3f, 0.7f, 1, 1, 1}, 2);
  check_next_to_knots<float>({0.499f, 0.4995f, 0.5f, 0.5005f, 0.501f, 0.6f, 0.8f, 0.9f}, 2);
  // Explicit values: 0.1f's neighbours.
  const std::vector<float> knots{0, 0, 0, 0.1f, 1, 1, 1};
  EXPECT_EQ(span_of(knots, 2, std::nextafter(0.1f, 0.0f)), 2);
  EXPECT_EQ(span_of(knots, 2, 0.1f), 3);
  EXPECT_EQ(span_of(knots, 2, std::nextafter(0.1f, 1.0f)), 3);
  EXPECT_EQ(span_of(knots, 2, 1.0f), 3);
}

template <typename T>
void check_random_spans(std::uint64_t seed) {
  Rng rng(seed);
  for (int degree = 1; degree <= kMaxDegree; ++degree)
    for (int trial = 0; trial < 40; ++trial) {
      const int count = degree + 1 + uniform_int(rng, 0, 12);
      const std::vector<double> kd =
          random_knots(rng, degree, count, Ends::mixed, uniform_int(rng, 0, 1) ? 0.125 : 0.1);
      const std::vector<T> knots(kd.begin(), kd.end());
      check_next_to_knots(knots, degree);
      for (int r = 0; r < 50; ++r) {
        const T u = static_cast<T>(uniform_real(rng, kd[degree] - 0.5, kd[count] + 0.5));
        ASSERT_EQ(find_span(degree, count, knots.data(), u), expected_span(knots, degree, count, u))
            << "degree " << degree << " u = " << u;
      }
    }
}

TEST(FindSpan, RandomKnotVectorsAgainstLinearScan) {
  check_random_spans<double>(11);
  check_random_spans<float>(12);
  check_random_spans<long double>(13);
}

TEST(BasisFunctions, NurbsBookEx23) {
  const nlohmann::json ex = load_test_data("peer_expected_values.json")["nurbsbook_ex2_3_basis"];
  const auto knots = ex["knots"].get<std::vector<double>>();
  const int degree = ex["degree"].get<int>(), span = ex["span"].get<int>();
  const double u = ex["u"].get<double>();
  // The expected values are exact binary fractions: checked to 1e-15, tighter than the book's
  // printed precision (the source's tol is 1e-7).
  const double tol = 1e-15;
  double basis[kMaxOrder];
  basis_functions(span, u, degree, knots.data(), basis);
  double ders[3][kMaxOrder];
  basis_function_derivatives(span, u, degree, 2, knots.data(), ders);
  const char* keys[3] = {"N", "dN", "d2N"};
  for (int j = 0; j <= degree; ++j) {
    EXPECT_NEAR(basis[j], ex["N"][j].get<double>(), tol) << "N[" << j << "]";
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(ders[k][j], ex[keys[k]][j].get<double>(), tol) << keys[k] << "[" << j << "]";
  }
}

TEST(BasisFunctions, OctaveNurbsTable) {
  const nlohmann::json ex = load_test_data("peer_expected_values.json")["octave_nurbs_basisfun"];
  const auto knots = ex["knots"].get<std::vector<double>>();
  const int degree = ex["degree"].get<int>();
  const double tol = ex["tol"].get<double>();  // the table is printed to 5 decimals
  const auto& rows = ex["N_rows"];
  ASSERT_EQ(rows.size(), 10u);
  Worst worst("octave basisfun table max |error|");
  for (int k = 0; k < 10; ++k) {
    const double u = k / 9.0;
    const int span = span_of(knots, degree, u);
    double basis[kMaxOrder];
    basis_functions(span, u, degree, knots.data(), basis);
    for (int j = 0; j <= degree; ++j) {
      const double expected = rows[k][j].get<double>();
      EXPECT_NEAR(basis[j], expected, tol) << "u = " << k << "/9, N[" << j << "]";
      worst.update(std::fabs(basis[j] - expected), [&] { return fmt::format("u={}/9", k); });
    }
  }
}

// For random valid knot vectors of degree 1..15 (clamped, unclamped, full-multiplicity interior
// knots): at the domain ends, every knot, both float neighbours of every knot and random u,
//   N_j >= 0 exactly, |sum N_j - 1| <= (degree+1) eps, and for k = 1, 2
//   |sum_j N_j^(k)| <= 4 (degree+1) eps sum_j |N_j^(k)|;
// basis_functions equals row 0 of basis_function_derivatives; everything finite (no 0/0 at u_max).
template <typename T>
void check_basis_properties(std::uint64_t seed, const char* type) {
  Rng rng(seed);
  const T eps = std::numeric_limits<T>::epsilon();
  Worst unity(fmt::format("{}: max |sum N - 1| / eps", type));
  Worst zero_sum(fmt::format("{}: max |sum N^(k)| / (eps sum |N^(k)|), k = 1, 2", type));
  for (int degree = 1; degree <= kMaxDegree; ++degree)
    for (int trial = 0; trial < 30; ++trial) {
      const int count = degree + 1 + uniform_int(rng, 0, 10);
      const std::vector<double> kd =
          random_knots(rng, degree, count, Ends::mixed, uniform_int(rng, 0, 1) ? 0.125 : 0.1);
      const std::vector<T> knots(kd.begin(), kd.end());
      std::vector<T> params;
      for (double t : test_parameters(rng, kd, degree, count, 30)) {
        const T u = static_cast<T>(t);
        params.push_back(u);
        if (u > knots[degree]) params.push_back(std::nextafter(u, knots[degree]));
        if (u < knots[count]) params.push_back(std::nextafter(u, knots[count]));
      }
      for (const T u : params) {
        const int span = find_span(degree, count, knots.data(), u);
        T basis[kMaxOrder];
        T ders[3][kMaxOrder];
        basis_functions(span, u, degree, knots.data(), basis);
        basis_function_derivatives(span, u, degree, 2, knots.data(), ders);
        auto where = [&] {
          return fmt::format("degree {} u {} knots [{}]", degree, static_cast<double>(u),
                             fmt::join(kd, ","));
        };
        T sum = 0, abs_sum[3] = {0, 0, 0}, der_sum[3] = {0, 0, 0};
        for (int j = 0; j <= degree; ++j) {
          ASSERT_TRUE(std::isfinite(basis[j])) << where();
          ASSERT_GE(basis[j], T(0)) << "N[" << j << "] " << where();
          ASSERT_LE(basis[j], T(1) + eps) << "N[" << j << "] " << where();
          ASSERT_NEAR(basis[j], ders[0][j], 2 * eps) << "j " << j << " " << where();
          sum += basis[j];
          for (int k = 0; k < 3; ++k) {
            ASSERT_TRUE(std::isfinite(ders[k][j])) << "k " << k << " j " << j << " " << where();
            abs_sum[k] += std::fabs(ders[k][j]);
            der_sum[k] += ders[k][j];
          }
        }
        const T unity_error = std::fabs(sum - 1) / eps;
        unity.update(static_cast<double>(unity_error), where);
        ASSERT_LE(unity_error, T(degree + 1)) << where();
        for (int k = 1; k <= 2; ++k) {
          if (abs_sum[k] == 0) continue;
          const T ratio = std::fabs(der_sum[k]) / (eps * abs_sum[k]);
          zero_sum.update(static_cast<double>(ratio), where);
          ASSERT_LE(ratio, T(4 * (degree + 1))) << "k " << k << " " << where();
        }
      }
    }
}

TEST(BasisFunctions, PartitionOfUnityAndNonNegativityDouble) {
  check_basis_properties<double>(21, "double");
}
TEST(BasisFunctions, PartitionOfUnityAndNonNegativityLongDouble) {
  check_basis_properties<long double>(22, "long double");
}
TEST(BasisFunctions, PartitionOfUnityAndNonNegativityFloat) {
  check_basis_properties<float>(23, "float");
}

// At u_max of a clamped knot vector the last basis function is 1 and the rest 0; the
// derivatives are those of the last span's polynomials (left limits), finite.
TEST(BasisFunctions, ClampedEndsInterpolate) {
  for (int degree = 1; degree <= kMaxDegree; ++degree) {
    const int count = degree + 3;
    std::vector<double> knots(static_cast<std::size_t>(count + degree + 1));
    for (std::size_t k = 0; k < knots.size(); ++k)
      knots[k] = std::clamp(static_cast<int>(k) - degree, 0, count - degree) / 3.0;
    for (const double u : {knots[degree], knots[count]}) {
      const int span = span_of(knots, degree, u);
      double basis[kMaxOrder];
      double ders[3][kMaxOrder];
      basis_functions(span, u, degree, knots.data(), basis);
      basis_function_derivatives(span, u, degree, 2, knots.data(), ders);
      const int one = u == knots[degree] ? 0 : degree;
      for (int j = 0; j <= degree; ++j) {
        EXPECT_EQ(basis[j], j == one ? 1.0 : 0.0) << "degree " << degree << " u " << u;
        for (int k = 0; k < 3; ++k)
          EXPECT_TRUE(std::isfinite(ders[k][j])) << "degree " << degree << " u " << u;
      }
    }
  }
}

// No floating-point division by zero or invalid operation (0/0, inf-inf) anywhere in the span
// search, A2.2 and A2.3 - at the domain ends, on every knot, next to knots - for random knot
// vectors of every degree with clamped, unclamped and full-multiplicity runs. (UBSan does not
// check floating-point division; the FP status flags do.)
TEST(BasisFunctions, NoDivisionByZeroAtEndsAndKnots) {
  Rng rng(24);
  for (int degree = 1; degree <= kMaxDegree; ++degree)
    for (int trial = 0; trial < 20; ++trial) {
      const int count = degree + 1 + uniform_int(rng, 0, 8);
      const std::vector<double> knots = random_knots(rng, degree, count, Ends::mixed);
      std::vector<double> params{knots[degree], knots[count]};
      for (int k = degree; k <= count; ++k)
        for (double t :
             {std::nextafter(knots[k], -INFINITY), knots[k], std::nextafter(knots[k], INFINITY)})
          if (t >= knots[degree] && t <= knots[count]) params.push_back(t);
      for (const double u : params) {
        std::feclearexcept(FE_ALL_EXCEPT);
        const int span = find_span(degree, count, knots.data(), u);
        double basis[kMaxOrder];
        double ders[3][kMaxOrder];
        basis_functions(span, u, degree, knots.data(), basis);
        basis_function_derivatives(span, u, degree, 2, knots.data(), ders);
        double sum = 0;  // use the results before reading the flags, so the work is not elided
        for (int j = 0; j <= degree; ++j) sum += basis[j] + ders[0][j] + ders[1][j] + ders[2][j];
        volatile double sink = sum;
        (void)sink;
        const int raised = std::fetestexcept(FE_DIVBYZERO | FE_INVALID | FE_OVERFLOW);
        ASSERT_EQ(raised, 0) << "FP exception " << raised << " at degree " << degree << " u " << u
                             << " knots [" << fmt::format("{}", fmt::join(knots, ",")) << "]";
      }
    }
}

// Rows of derivatives above the degree are zero (a linear B-spline has no second derivative).
TEST(BasisFunctions, DerivativesAboveTheDegreeAreZero) {
  const std::vector<double> knots{0, 0, 0.5, 1, 1};
  double ders[3][kMaxOrder];
  basis_function_derivatives(1, 0.25, 1, 2, knots.data(), ders);
  EXPECT_DOUBLE_EQ(ders[0][0], 0.5);
  EXPECT_DOUBLE_EQ(ders[0][1], 0.5);
  EXPECT_DOUBLE_EQ(ders[1][0], -2.0);
  EXPECT_DOUBLE_EQ(ders[1][1], 2.0);
  EXPECT_EQ(ders[2][0], 0.0);
  EXPECT_EQ(ders[2][1], 0.0);
}

}  // namespace
}  // namespace nurbs::test
