// gl-pingpong's 000 §3.2 render path (strategies/gl_pingpong/lod_renderer.h): every surface on a
// grid of its own, changed between frames, drawn from its output copied on the device. The
// vertex buffers the frame drew are read back here (and only here) and compared with the
// extended-precision reference at their samples within gl-pingpong's gate; the context's counters
// show the frame itself read nothing back to the host.
#include "strategies/gl_pingpong/lod_renderer.h"

#include <gtest/gtest.h>

#include <iostream>

#include "harness/metrics.h"
#include "reference/reference_evaluator.h"
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

TEST(GlPingPongLod, RefusesTrimmedScenesAndGridsPastOneTexture) {
  const Availability a = gl::Context::probe_any();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  StrategyOptions options;
  options.extra["gl"] = gl::Context::probe(gl::Platform::egl).available ? "egl" : "osmesa";
  EXPECT_THROW(
      gl_pingpong::make_lod_renderer(*make_builtin_scene("trimmed-plate"), 32, 32, options),
      RefusedError);
  const auto renderer =
      gl_pingpong::make_lod_renderer(*make_builtin_scene("patch144"), 32, 32, options);
  EXPECT_THROW(renderer->set_grid(0, 1, 8), RefusedError);
  EXPECT_THROW(renderer->set_grid(0, 8, 1 << 20), RefusedError);
}

}  // namespace
}  // namespace nurbs
