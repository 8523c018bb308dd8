// 000 §4's trim texture in the GL strategies that trim (gl-pingpong, gl-pingpong-packed,
// glsl-deboor), against the reference's exact classification (reference/trim_classify.h, long
// double), the oracle: on trimmed-plate and hammer,
//  - every misclassified sample outside the band lies within the derived distance d of the exact
//    boundary (trim_texture::misclassification_distance, strategies/trim_texture/trim_polygons.h):
//      d = (1/2 + 2^-(s+1)) * sqrt(h_u^2 + h_v^2) + tol,   h_u = du / R, h_v = dv / R,
//    half a texel diagonal (a sample reads the texel whose centre is nearest, and that texel holds
//    the polygon's parity at its centre), the rasterizer's vertex snapping to 2^-s of a texel
//    (s = GL_SUBPIXEL_BITS) and the chordal tolerance (a point where polygon and curves disagree is
//    within tol of the curves);
//  - hence the misclassification rate is at most the stated bound, computed from the loops:
//    each grid sample within d of the boundary owns its grid cell (g_u x g_v, centred on it), all
//    of which lies within r = d + sqrt(g_u^2 + g_v^2) / 2 of the boundary, and cells are disjoint;
//    the r-neighbourhood of a loop of length L has area at most 2 r L + pi r^2, so
//      misclassified <= sum over trimmed surfaces and loops of (2 r L + pi r^2) / (g_u g_v),
//    divided by the samples outside the band. L is taken from the loop's polygon at a tolerance of
//    1e-9 of the diagonal (it converges to the curve length from below) plus 1%;
//  - the rate falls as R grows, and a coarse tessellation misclassifies more than a fine one.
// And the render phase: trimmed-plate drawn with its trim shows the background inside the hole,
// untrimmed it does not.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>

#include "reference/sampling.h"
#include "reference/trim_classify.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_context/grid_renderer.h"
#include "strategies/registry.h"
#include "strategies/trim_texture/trim_polygons.h"

namespace nurbs {
namespace {

constexpr double kBand = 1e-7;  // the harness's default --trim-band

struct Oracle {
  std::vector<TrimClassification> surfaces;  // empty classification for untrimmed surfaces
};

const Oracle& oracle(const std::string& scene_name, const Scene& scene,
                     const std::vector<SurfaceSamples>& samples) {
  static std::map<std::string, Oracle> cache;
  auto [it, added] = cache.try_emplace(scene_name);
  if (added)
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
      it->second.surfaces.push_back(scene.surfaces[i].trim
                                        ? classify_trim_samples(*scene.surfaces[i].trim, samples[i],
                                                                true, TrimScalar::long_double)
                                        : TrimClassification{});
  return it->second;
}

struct Outcome {
  std::size_t scored = 0, misclassified = 0, near = 0;
  double bound_count = 0;           // the analytic bound on `near`, hence on `misclassified`
  double worst_distance_ratio = 0;  // max over misclassified samples of distance / d
  double rate() const { return scored ? static_cast<double>(misclassified) / scored : 0; }
  double bound() const { return scored ? bound_count / scored : 0; }
};

Sampling grid(int n) {
  Sampling s;
  s.grid_u = n;
  s.grid_v = n;
  return s;
}

Outcome measure(const std::string& strategy_name, const std::string& scene_name, int resolution,
                double tolerance, int n) {
  const Scene scene = *make_builtin_scene(scene_name);
  const Sampling sampling = grid(n);
  const std::vector<SurfaceSamples> samples = sample_parameters(scene, sampling);
  StrategyOptions options;
  options.extra["trim-resolution"] = std::to_string(resolution);
  options.extra["trim-tolerance"] = fmt::format("{}", tolerance);
  auto strategy = find_strategy(strategy_name)->create(options);
  strategy->prepare(scene, EvalRequest{sampling, Precision::f32, false});
  strategy->evaluate();
  EXPECT_TRUE(strategy->classify());
  const EvalResult result = strategy->read_back();
  const DeviceInfo device = strategy->device();
  EXPECT_EQ(device.details.at("trim_resolution"), std::to_string(resolution));
  const int subpixel_bits = std::stoi(device.details.at("trim_subpixel_bits"));
  const Oracle& truth = oracle(scene_name, scene, samples);

  Outcome out;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& surface = scene.surfaces[i];
    const std::vector<std::uint8_t>& inside = result.surfaces[i].inside;
    if (!surface.trim) {
      EXPECT_TRUE(inside.empty());
      continue;
    }
    const SurfaceSamples& s = samples[i];
    EXPECT_EQ(result.surfaces[i].samples.u, s.u);
    EXPECT_EQ(result.surfaces[i].samples.v, s.v);
    if (inside.size() != s.count()) {
      ADD_FAILURE() << surface.name << ": mask of " << inside.size() << " for " << s.count();
      continue;
    }
    const double du = surface.u_max() - surface.u_min(), dv = surface.v_max() - surface.v_min();
    const double diagonal = domain_diagonal(surface);
    // The bound itself is held to hand-computed values in trim_polygons_test.
    const double d = trim_texture::misclassification_distance(du, dv, resolution,
                                                              tolerance * diagonal, subpixel_bits);
    // trim_classify.h: the distance is within 1% (and 1e-12 of the loops' extent).
    const double d_checked = d * 1.01 + 1e-12 * diagonal;
    const TrimClassification& exact = truth.surfaces[i];
    for (std::size_t k = 0; k < s.count(); ++k) {
      const double distance = exact.distance[k];
      if (distance < kBand * diagonal) continue;
      ++out.scored;
      if (distance <= d_checked) ++out.near;
      if (inside[k] != exact.inside[k]) {
        ++out.misclassified;
        out.worst_distance_ratio = std::max(out.worst_distance_ratio, distance / d);
        EXPECT_LE(distance, d_checked)
            << strategy_name << " R=" << resolution << " " << surface.name << " sample ("
            << s.u_of(k) << ", " << s.v_of(k) << ") misclassified " << distance / d
            << " x d from the boundary";
      }
    }
    const double gu = du / (s.u.size() - 1), gv = dv / (s.v.size() - 1);
    const double r = d_checked + 0.5 * std::hypot(gu, gv);
    for (const auto& polygon : trim_texture::trim_polygons(*surface.trim, 1e-9 * diagonal)) {
      double length = 0;
      for (std::size_t j = 0; j < polygon.size(); ++j) {
        const Point2& a = polygon[j];
        const Point2& b = polygon[(j + 1) % polygon.size()];
        length += std::hypot(b[0] - a[0], b[1] - a[1]);
      }
      out.bound_count += (2 * r * length * 1.01 + M_PI * r * r) / (gu * gv);
    }
  }
  EXPECT_LE(out.misclassified, out.near);
  return out;
}

class TrimTexture : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    const StrategyEntry* entry = find_strategy(GetParam());
    ASSERT_NE(entry, nullptr);
    if (!entry->probe().available) GTEST_SKIP() << entry->probe().reason;
    ASSERT_TRUE(entry->capabilities().trims);
  }
};

TEST_P(TrimTexture, MisclassifiedOnlyWithinTheDerivedDistanceAndRateBelowTheBound) {
  for (const std::string scene : {"trimmed-plate", "hammer"}) {
    double previous = 2;
    std::vector<double> rates;
    for (int resolution : {64, 256, 1024}) {
      const Outcome o = measure(GetParam(), scene, resolution, 1e-5, 128);
      SCOPED_TRACE(scene + " R=" + std::to_string(resolution));
      ASSERT_GT(o.scored, 10000u);
      EXPECT_LE(o.rate(), o.bound());
      EXPECT_LT(o.bound(), 1.0) << "a bound that says nothing";
      EXPECT_LE(o.rate(), previous) << "a finer texture misclassifies no more";
      previous = o.rate();
      rates.push_back(o.rate());
      std::cout << GetParam() << " " << scene << " R=" << resolution << ": rate " << o.rate()
                << " (" << o.misclassified << " of " << o.scored << "), within d " << o.near
                << ", bound " << o.bound() << ", worst distance/d " << o.worst_distance_ratio
                << "\n";
    }
    EXPECT_GT(rates.front(), 0.0) << scene << ": R=64 is coarse enough to misclassify";
    EXPECT_LT(rates.back(), rates.front() / 4) << scene;
  }
}

TEST_P(TrimTexture, CoarseTessellationMisclassifiesMore) {
  // At R = 4096 the texel term is small next to a tolerance of 1e-2 of the diagonal, whose
  // 16-gon-like circle cuts off visible slivers of the hole.
  const Outcome coarse = measure(GetParam(), "trimmed-plate", 4096, 1e-2, 128);
  const Outcome fine = measure(GetParam(), "trimmed-plate", 4096, 1e-6, 128);
  EXPECT_LE(coarse.rate(), coarse.bound());
  EXPECT_GT(coarse.misclassified, fine.misclassified);
}

TEST_P(TrimTexture, BadOptionsAreRefusedByName) {
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, std::string>>{{"trim-resolution", "32"},
                                                        {"trim-resolution", "5000"},
                                                        {"trim-resolution", "1k"},
                                                        {"trim-tolerance", "0"},
                                                        {"trim-tolerance", "-1e-3"},
                                                        {"trim-tolerance", "abc"},
                                                        {"trim-tolerance", "0.5"}}) {
    StrategyOptions options;
    options.extra[key] = value;
    try {
      find_strategy(GetParam())->create(options);
      ADD_FAILURE() << key << "=" << value << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key + " = '" + value + "'"), std::string::npos)
          << e.what();
    }
  }
}

// The render phase: pixels where the plate's hole is (samples the oracle puts well inside the
// hole, projected with the strategy's view) are background with the trim and covered without it;
// pixels well inside the face are covered either way.
TEST_P(TrimTexture, RenderShowsTheBackgroundThroughTheHole) {
  const Scene trimmed = *make_builtin_scene("trimmed-plate");
  Scene untrimmed = trimmed;
  untrimmed.surfaces[0].trim.reset();
  const Sampling sampling = grid(64);
  const SurfaceSamples samples = sample_parameters(trimmed, sampling)[0];
  const TrimClassification exact =
      classify_trim_samples(*trimmed.surfaces[0].trim, samples, true, TrimScalar::long_double);
  const std::array<float, 16> view = gl::orthographic_view(trimmed);
  auto covered_at = [&](const RenderedImage& image, const float* p) {
    const float x = view[0] * p[0] + view[4] * p[1] + view[8] * p[2] + view[12];
    const float y = view[1] * p[0] + view[5] * p[1] + view[9] * p[2] + view[13];
    const int px = static_cast<int>((x + 1) / 2 * image.width);
    const int row = image.height - 1 - static_cast<int>((y + 1) / 2 * image.height);
    return image.rgba[(static_cast<std::size_t>(row) * image.width + px) * 4 + 3] != 0;
  };
  std::map<bool, RenderedImage> images;
  EvalResult positions;
  for (bool with_trim : {true, false}) {
    auto strategy = find_strategy(GetParam())->create({});
    EXPECT_FALSE(strategy->last_render()) << "nothing drawn yet";
    strategy->prepare(with_trim ? trimmed : untrimmed,
                      EvalRequest{sampling, Precision::f32, false});
    strategy->evaluate();
    ASSERT_TRUE(strategy->render());
    std::optional<RenderedImage> image = strategy->last_render();
    ASSERT_TRUE(image);
    ASSERT_EQ(image->rgba.size(), static_cast<std::size_t>(image->width) * image->height * 4);
    images[with_trim] = std::move(*image);
    positions = strategy->read_back();
  }
  int hole = 0, face = 0;
  const float* xyz = positions.surfaces[0].positions.f32();
  for (std::size_t k = 0; k < samples.count(); ++k) {
    // 0.05 in (u, v) is several pixels of the 512-pixel image: away from edge effects.
    if (exact.distance[k] < 0.05) continue;
    const float* p = xyz + 3 * k;
    const bool in_hole = std::hypot(samples.u_of(k) - 0.5, samples.v_of(k) - 0.5) < 0.2;
    if (in_hole) {
      ++hole;
      EXPECT_FALSE(covered_at(images[true], p)) << "hole sample " << k << " drawn";
      EXPECT_TRUE(covered_at(images[false], p)) << "untrimmed sample " << k << " not drawn";
    } else if (exact.inside[k]) {
      ++face;
      EXPECT_TRUE(covered_at(images[true], p)) << "face sample " << k << " not drawn";
      EXPECT_TRUE(covered_at(images[false], p));
    }
  }
  EXPECT_GT(hole, 20);
  EXPECT_GT(face, 200);
}

// Test names carry the strategy as ctest -R selects it (gl_pingpong, glsl_deboor).
const std::map<std::string, std::string> kTestNames = {{"gl-pingpong", "gl_pingpong"},
                                                       {"gl-pingpong-packed", "gl_pingpong_packed"},
                                                       {"glsl-deboor", "glsl_deboor"}};
INSTANTIATE_TEST_SUITE_P(Strategies, TrimTexture,
                         ::testing::Values("gl-pingpong", "gl-pingpong-packed", "glsl-deboor"),
                         [](const auto& info) { return kTestNames.at(info.param); });

}  // namespace
}  // namespace nurbs
