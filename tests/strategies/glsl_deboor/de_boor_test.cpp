// The CPU copy of de Boor in homogeneous coordinates (strategies/glsl_deboor/de_boor.h, which
// de_boor.frag mirrors) against the A4.3 basis-function evaluator nurbs::surface_point, and the
// host binning of parameters into knot spans against FindSpan.
#include "strategies/glsl_deboor/de_boor.h"

#include <gtest/gtest.h>

#include <cmath>

#include "reference/sampling.h"
#include "scenes/builtin_scenes.h"
#include "strategies/glsl_deboor/span_runs.h"

namespace nurbs::glsl_deboor {
namespace {

const std::vector<std::string> kScenes = {"patch144",  "sphere",   "torus",    "degree-1",
                                          "degree-2",  "degree-5", "degree-9", "creases",
                                          "clustered", "teapot",   "many-16"};

template <typename T>
double largest_coordinate(const Scene& scene) {
  double m = 0;
  for (const Surface& s : scene.surfaces)
    for (const auto& p : s.points)
      for (double c : p) m = std::max(m, std::abs(c));
  return m;
}

// In long double the two algorithms agree to rounding; in double too (a few ulps).
template <typename T>
void expect_agreement(const std::string& scene_name, double tolerance_eps) {
  const Scene scene = *make_builtin_scene(scene_name);
  const double scale = largest_coordinate<T>(scene);
  Sampling span;
  span.mode = SamplingMode::span_grid;
  span.span_steps = 3;
  for (const Sampling& sampling : {Sampling{}, span}) {
    const auto samples = sample_parameters(scene, sampling);
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& surface = scene.surfaces[i];
      const SurfaceNet<T> net(surface);
      const auto runs_u =
          bin_into_spans(samples[i].u, surface.degree_u, surface.count_u, surface.knots_u);
      const auto runs_v =
          bin_into_spans(samples[i].v, surface.degree_v, surface.count_v, surface.knots_v);
      for (const SpanRun& ru : runs_u)
        for (int a = ru.first; a < ru.first + ru.count; ++a)
          for (const SpanRun& rv : runs_v)
            for (int b = rv.first; b < rv.first + rv.count; ++b) {
              const T u = T(samples[i].u[a]), v = T(samples[i].v[b]);
              const Vec3<T> got = surface_point_de_boor(net, ru.span, u, rv.span, v);
              const Vec3<T> want = surface_point(net, u, v);
              for (int c = 0; c < 3; ++c)
                ASSERT_NEAR(double(got[c]), double(want[c]), tolerance_eps * scale)
                    << scene_name << " surface " << i << " u=" << samples[i].u[a]
                    << " v=" << samples[i].v[b];
            }
    }
  }
}

TEST(DeBoor, AgreesWithBasisFunctionsInLongDouble) {
  for (const std::string& s : kScenes) expect_agreement<long double>(s, 1e-15);
}

TEST(DeBoor, AgreesWithBasisFunctionsInFloat) {
  for (const std::string& s : kScenes) expect_agreement<float>(s, 64 * 1.2e-7);
}

// A hand-checked case: quadratic, knots {0,0,0,1,2,2,2}, u = 0.5 in span 2 (P&T Ex. 2.3 basis:
// N = 1/8... ), control points 0, 1, 2, 3 on a line reproduce the Greville abscissae map.
TEST(DeBoor, LinearPrecision) {
  const double knots[] = {0, 0, 0, 1, 2, 2, 2};
  double K[4];
  span_knots(2, 2, knots, K);
  EXPECT_EQ(K[0], 0.0);
  EXPECT_EQ(K[1], 0.0);
  EXPECT_EQ(K[2], 1.0);
  EXPECT_EQ(K[3], 2.0);
  // Control points at the Greville abscissae (u_{i+1} + u_{i+2}) / 2 reproduce x(u) = u.
  Vec4<double> d[3] = {{0, 0, 0, 1}, {0.5, 0, 0, 1}, {1.5, 0, 0, 1}};
  const Vec4<double> p = de_boor(2, K, 0.5, d);
  EXPECT_DOUBLE_EQ(p[0], 0.5);
  EXPECT_DOUBLE_EQ(p[3], 1.0);
}

TEST(SpanRuns, OneRunPerNonEmptySpanWithSamples) {
  // Cubic, spans [0,0.1) [0.1,0.5) [0.5,0.5) empty, [0.5,1]; samples on a 11-point grid.
  const std::vector<double> knots = {0, 0, 0, 0, 0.1, 0.5, 0.5, 1, 1, 1, 1};
  const std::vector<double> u = grid_parameters(0, 1, 11);
  const auto runs = bin_into_spans(u, 3, 7, knots);
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0].span, 3);
  EXPECT_EQ(runs[0].first, 0);
  EXPECT_EQ(runs[0].count, 1);  // 0.0
  EXPECT_EQ(runs[1].span, 4);
  EXPECT_EQ(runs[1].count, 4);  // 0.1 .. 0.4
  EXPECT_EQ(runs[2].span, 6);   // past the empty span [0.5, 0.5)
  EXPECT_EQ(runs[2].first, 5);
  EXPECT_EQ(runs[2].count, 6);  // 0.5 .. 1.0: the end belongs to the last span
  for (const SpanRun& r : runs)
    for (int a = r.first; a < r.first + r.count; ++a)
      EXPECT_EQ(find_span(3, 7, knots.data(), u[a]), r.span);
}

}  // namespace
}  // namespace nurbs::glsl_deboor
