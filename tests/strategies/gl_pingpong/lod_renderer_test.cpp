// gl-pingpong's 000 §3.2 render path (strategies/gl_pingpong/lod_renderer.h): every surface on a
// grid of its own, changed between frames, drawn from its output copied on the device. The
// vertex buffers the frame drew are read back here (and only here) and compared with the
// extended-precision reference at their samples within gl-pingpong's gate; the context's counters
// show the frame itself read nothing back to the host.
#include "strategies/gl_pingpong/lod_renderer.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "harness/metrics.h"
#include "reference/reference_evaluator.h"
#include "reference/sampling.h"
#include "reference/trim_classify.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_pingpong/camera_lod.h"

namespace nurbs {
namespace {

// results/gates.json: gl-pingpong, every scene, max_ulp.
constexpr double kGateUlp = 32.0;

TEST(GlPingPongLod, DrawsTheEvaluatedPointsFromADeviceCopyWithoutReadBack) {
  for (gl::Platform platform : {gl::Platform::osmesa, gl::Platform::egl}) {
    SCOPED_TRACE(std::string(gl::to_string(platform)));
    const Availability a = gl::Context::probe(platform);
    if (!a.available) {
      std::cout << "skipped " << gl::to_string(platform) << ": " << a.reason << "\n";
      continue;
    }
    const Scene scene = *make_builtin_scene("teapot");
    StrategyOptions options;
    options.extra["gl"] = std::string(gl::to_string(platform));
    const auto renderer = gl_pingpong::make_lod_renderer(scene, 96, 64, options);
    const gl_pingpong::FlyIn path = gl_pingpong::fly_in_of(scene);
    for (int frame = 0; frame < 2; ++frame) {
      SCOPED_TRACE(frame);
      // Grids that differ per surface, between u and v, and between the two frames.
      std::uint64_t expected_triangles = 0;
      std::vector<std::pair<int, int>> grids;
      for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
        const int nu = 2 + static_cast<int>((i * 5 + frame * 7) % 13);
        const int nv = 2 + static_cast<int>((i * 3 + frame * 4) % 11);
        renderer->set_grid(i, nu, nv);
        grids.emplace_back(nu, nv);
        expected_triangles += 2ull * (nu - 1) * (nv - 1);
      }
      const gl_pingpong::LodCounts before = renderer->counts();
      const std::uint64_t triangles = renderer->draw_frame(
          gl_pingpong::view_projection(gl_pingpong::camera_at(path, frame, 2, 96, 64)));
      const gl_pingpong::LodCounts after = renderer->counts();
      EXPECT_EQ(triangles, expected_triangles);
      EXPECT_EQ(after.host_read_backs, before.host_read_backs);
      EXPECT_EQ(after.device_copies - before.device_copies, scene.surfaces.size());
      // Per surface at least the basis passes, k_u k_v accumulations, the divide and its draw.
      EXPECT_GE(after.draws - before.draws, scene.surfaces.size() * (2 + 16 + 1 + 1));

      // The picture is not empty: the triangles reached the image.
      const RenderedImage image = renderer->picture();
      std::size_t covered = 0;
      for (std::size_t p = 3; p < image.rgba.size(); p += 4) covered += image.rgba[p] != 0;
      EXPECT_GT(covered, 0u);

      const gl_pingpong::LodCounts before_read = renderer->counts();
      EvalResult drawn;
      drawn.surfaces = renderer->read_vertex_buffers();
      // The test's read is the one the counter sees.
      EXPECT_EQ(renderer->counts().host_read_backs - before_read.host_read_backs,
                scene.surfaces.size());
      ASSERT_EQ(drawn.surfaces.size(), scene.surfaces.size());
      std::vector<SurfaceSamples> samples;
      for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
        const SurfaceResult& r = drawn.surfaces[i];
        const Surface& s = scene.surfaces[i];
        ASSERT_EQ(r.samples.u.size(), static_cast<std::size_t>(grids[i].first));
        ASSERT_EQ(r.samples.v.size(), static_cast<std::size_t>(grids[i].second));
        EXPECT_EQ(r.samples.u, grid_parameters(s.u_min(), s.u_max(), grids[i].first));
        EXPECT_EQ(r.samples.v, grid_parameters(s.v_min(), s.v_max(), grids[i].second));
        ASSERT_EQ(r.positions.size(), r.samples.count());
        samples.push_back(r.samples);
      }
      const Accuracy acc =
          measure_accuracy(scene, drawn, evaluate_reference(scene, samples, false));
      EXPECT_EQ(acc.non_finite, 0u);
      EXPECT_LE(acc.max_ulp, kGateUlp) << "surface " << acc.worst_surface << " at (" << acc.worst_u
                                       << ", " << acc.worst_v << ")";
    }
  }
}

// 000's own example, the trimmed duck (many-ducks-1: each of its three surfaces trimmed to a
// rounded rectangle with a hole), drawn by the LOD path with its trim texture. Independently of
// the texture: the surfaces are sampled densely, evaluated and classified by the reference, and
// projected with the same camera. A pixel onto which only samples the reference puts outside the
// trim project (more than kBand of the domain diagonal from the boundary, and more than kMargin
// pixels from any other sample's projection) and covered by the same scene drawn without its
// trims (so the check can fail) must stay empty, and the trimmed duck is not empty.
TEST(GlPingPongLod, DrawsTheTrimmedDuckWithoutItsTrimmedAwayParts) {
  const Availability a = gl::Context::probe_any();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  StrategyOptions options;
  options.extra["gl"] = gl::Context::probe(gl::Platform::egl).available ? "egl" : "osmesa";
  // A grid longer in u than in v, so a lookup with u and v exchanged cannot pass for the right one.
  constexpr int kWidth = 256, kHeight = 192, kGridU = 64, kGridV = 40, kDense = 256, kMargin = 2;
  // Trim texture (1/1024 of the domain) and the mesh's chords stay well inside these.
  constexpr double kBand = 0.01;
  const Scene trimmed = *make_builtin_scene("many-ducks-1");
  Scene whole = trimmed;
  for (Surface& s : whole.surfaces) {
    ASSERT_TRUE(s.trim);
    s.trim.reset();
  }
  const gl_pingpong::Camera camera =
      gl_pingpong::camera_at(gl_pingpong::fly_in_of(trimmed), 3, 4, kWidth, kHeight);
  auto draw = [&](const Scene& scene) {
    const auto renderer = gl_pingpong::make_lod_renderer(scene, kWidth, kHeight, options);
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) renderer->set_grid(i, kGridU, kGridV);
    renderer->draw_frame(gl_pingpong::view_projection(camera));
    return renderer->picture();
  };
  const RenderedImage with_trim = draw(trimmed), without_trim = draw(whole);
  auto covered = [&](const RenderedImage& image, int x, int y) {
    // picture() rows run top to bottom; window y runs upwards.
    return image.rgba[(static_cast<std::size_t>(kHeight - 1 - y) * kWidth + x) * 4 + 3] != 0;
  };

  std::vector<SurfaceSamples> samples;
  for (const Surface& s : trimmed.surfaces) {
    SurfaceSamples g;
    g.u = grid_parameters(s.u_min(), s.u_max(), kDense);
    g.v = grid_parameters(s.v_min(), s.v_max(), kDense);
    samples.push_back(std::move(g));
  }
  const std::vector<ReferenceSurface> reference = evaluate_reference(trimmed, samples, false);
  // Pixels that something other than a clearly-outside sample may cover, dilated by kMargin.
  std::vector<std::uint8_t> may_cover(static_cast<std::size_t>(kWidth) * kHeight, 0);
  std::vector<std::array<int, 2>> outside_pixels;
  for (std::size_t i = 0; i < trimmed.surfaces.size(); ++i) {
    const double band = kBand * domain_diagonal(trimmed.surfaces[i]);
    const ReferenceSurface& r = reference[i];
    for (std::size_t k = 0; k < r.positions.size(); ++k) {
      const auto p = gl_pingpong::project_to_pixels(camera, r.positions[k]);
      ASSERT_TRUE(p);
      const int x = static_cast<int>(std::floor((*p)[0])),
                y = static_cast<int>(std::floor((*p)[1]));
      if (r.inside[k] == 0 && r.trim_distance[k] > band) {
        if (x >= 0 && x < kWidth && y >= 0 && y < kHeight) outside_pixels.push_back({x, y});
        continue;
      }
      for (int yy = std::max(y - kMargin, 0); yy <= std::min(y + kMargin, kHeight - 1); ++yy)
        for (int xx = std::max(x - kMargin, 0); xx <= std::min(x + kMargin, kWidth - 1); ++xx)
          may_cover[static_cast<std::size_t>(yy) * kWidth + xx] = 1;
    }
  }
  // Checked: those pixels the duck drawn without its trims covers (the rest lie off its mesh,
  // at silhouettes where the 64x40 mesh's chords and the dense samples part by a pixel or two).
  std::size_t only_outside = 0, checked = 0, drawn_with_trim = 0;
  std::vector<std::uint8_t> seen(may_cover.size(), 0);
  for (const auto& [x, y] : outside_pixels) {
    const std::size_t pixel = static_cast<std::size_t>(y) * kWidth + x;
    if (may_cover[pixel] || seen[pixel]) continue;
    seen[pixel] = 1;
    ++only_outside;
    if (!covered(without_trim, x, y)) continue;
    ++checked;
    if (covered(with_trim, x, y)) {
      ++drawn_with_trim;
      ADD_FAILURE() << "pixel (" << x << ", " << y
                    << ") drawn; only trimmed-away parts project there";
    }
  }
  std::size_t duck = 0;
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) duck += covered(with_trim, x, y);
  std::printf(
      "trimmed duck: %zu pixels only trimmed-away parts project to, %zu of them drawn "
      "without the trim; %zu of those drawn with it; %zu pixels drawn in all\n",
      only_outside, checked, drawn_with_trim, duck);
  EXPECT_GE(checked, 100u);
  EXPECT_GE(checked, only_outside * 3 / 4);
  EXPECT_EQ(drawn_with_trim, 0u);
  EXPECT_GT(duck, 1000u);
}

TEST(GlPingPongLod, RefusesGridsPastOneTexture) {
  const Availability a = gl::Context::probe_any();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  StrategyOptions options;
  options.extra["gl"] = gl::Context::probe(gl::Platform::egl).available ? "egl" : "osmesa";
  const auto renderer =
      gl_pingpong::make_lod_renderer(*make_builtin_scene("patch144"), 32, 32, options);
  EXPECT_THROW(renderer->set_grid(0, 1, 8), RefusedError);
  EXPECT_THROW(renderer->set_grid(0, 8, 1 << 20), RefusedError);
}

}  // namespace
}  // namespace nurbs
