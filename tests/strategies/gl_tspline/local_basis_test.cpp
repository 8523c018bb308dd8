// The C++ builds of gl-tspline's single-source local basis (strategies/gl_tspline/local_basis.h;
// accumulate.frag runs the same text as GLSL) against the reference's local_basis (Piegl &
// Tiller A2.2/A2.3 on the padded local knots, reference/tspline.h), on random local knot vectors
// with repeated knots, every odd degree, every non-empty span.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>

#include "reference/tspline.h"
#include "strategies/gl_tspline/local_basis_cpp.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"

namespace nurbs::gl_tspline {
namespace {

using LD = long double;

TEST(GlTSplineLocalBasis, BuildsAgreeWithReference) {
  test::Rng rng(61);
  test::Worst ld_error("max |long double build - reference| (value, derivative x width)");
  test::Worst float_error("max |float build - reference| / FLT_EPSILON (value)");
  for (int degree = 1; degree <= kMaxDegree; degree += 2)
    for (int trial = 0; trial < 20; ++trial) {
      // degree + 2 dyadic knots, repeats allowed (but a non-empty support): exact in float.
      std::vector<double> k{test::uniform_int(rng, -8, 8) / 8.0};
      for (int i = 1; i < degree + 2; ++i)
        k.push_back(k.back() +
                    (test::uniform_int(rng, 0, 2) == 0 ? 0.0 : test::uniform_int(rng, 1, 8) / 8.0));
      if (!(k.front() < k.back())) continue;
      const double width = k.back() - k.front();
      std::vector<float> kf(k.begin(), k.end());
      std::vector<LD> kl(k.begin(), k.end());
      for (int span = 0; span <= degree; ++span) {
        if (!(k[span] < k[span + 1])) continue;
        for (int s = 0; s <= 8; ++s) {
          const float tf = static_cast<float>(k[span] + (k[span + 1] - k[span]) * s / 8.0);
          const double t = tf;
          LD ref[3];
          local_basis(degree, k.data(), span, LD(t), 1, ref);
          LD value = 0, derivative = 0;
          source::lb_local_basis(degree, kl.data(), span, LD(t), value, derivative);
          const auto where = [&] { return fmt::format("degree {} span {} t {}", degree, span, t); };
          const double ev = static_cast<double>(std::fabs(value - ref[0]));
          const double ed = static_cast<double>(std::fabs(derivative - ref[1])) * width;
          ld_error.update(std::max(ev, ed), where);
          ASSERT_LE(ev, 64 * LDBL_EPSILON) << where();
          ASSERT_LE(ed, 64 * degree * LDBL_EPSILON) << where();
          float vf = 0, df = 0;
          source::lb_local_basis(degree, kf.data(), span, tf, vf, df);
          // Each order costs at most 2 roundings per ratio term (exact float differences of exact
          // floats): 4 degree float epsilons on a value <= 1.
          const double e = std::fabs(static_cast<double>(vf) - static_cast<double>(ref[0]));
          float_error.update(e / FLT_EPSILON, where);
          ASSERT_LE(e, 4.0 * degree * FLT_EPSILON) << where();
        }
      }
    }
}

}  // namespace
}  // namespace nurbs::gl_tspline
