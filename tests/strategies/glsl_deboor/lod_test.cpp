// 002 §4.3: Haar-wavelet levels of the evaluated tan21x23 surface (the paper's Fig 15 net). The
// forward + inverse round trip is not bit-for-bit: A = (a0 + a1) / 2, D = (a0 - a1) / 2 and A + D
// each round once (the halving is exact), so one 1D step returns a0 within 1.5 ulp of the
// largest coordinate and one level (row + column step) within 3; three levels within 9. Level 1
// is the 2x2 averages of level 0 (row step, then column step). Fig 15's timings and each level's
// distance to the surface: `nurbsbench lod` (tested at the end).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "../../cli/run_cli.h"
#include "reference/nurbs_math.h"
#include "reference/sampling.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_context/grid_renderer.h"
#include "strategies/glsl_deboor/haar_lod.h"

namespace nurbs::glsl_deboor {
namespace {

float largest(const std::vector<float>& xyz) {
  float m = 0;
  for (float c : xyz) m = std::max(m, std::abs(c));
  return m;
}

TEST(GlslDeBoorLod, ForwardInverseRoundTripWithinTheRoundingBound) {
  if (!gl::Context::probe(gl::Platform::egl).available) GTEST_SKIP();
  auto context = gl::Context::create(gl::Platform::egl);
  const Scene scene = *make_builtin_scene("tan21x23");
  Sampling grid;
  grid.grid_u = 128;
  grid.grid_v = 64;
  Evaluator evaluator(*context, context->max_texture_size());
  evaluator.prepare(scene, sample_parameters(scene, grid));
  evaluator.evaluate();
  const std::vector<float> level0 = evaluator.read_back()[0];
  HaarLod lod(*context, evaluator.pages()[0], evaluator.pages()[0].slots[0], 3);
  for (int k = 0; k < 3; ++k) lod.forward(k);
  EXPECT_EQ(lod.width(3), 16);
  EXPECT_EQ(lod.height(3), 8);
  // Level 1 = averages of 2x2 blocks, rows first: A = (A_row(b) + A_row(b+1)) / 2.
  const std::vector<float> level1 = lod.read(1);
  const float ulp = largest(level0) * FLT_EPSILON;
  for (int a = 0; a < 64; ++a)
    for (int b = 0; b < 32; ++b)
      for (int c = 0; c < 3; ++c) {
        auto p = [&](int i, int j) {
          return level0[(static_cast<std::size_t>(i) * 64 + j) * 3 + c];
        };
        const float r0 = 0.5f * (p(2 * a, 2 * b) + p(2 * a + 1, 2 * b));
        const float r1 = 0.5f * (p(2 * a, 2 * b + 1) + p(2 * a + 1, 2 * b + 1));
        ASSERT_NEAR(level1[(static_cast<std::size_t>(a) * 32 + b) * 3 + c], 0.5f * (r0 + r1), ulp);
      }
  auto worst_ulp = [&](const std::vector<float>& back) {
    EXPECT_EQ(back.size(), level0.size());
    float worst = 0;
    for (std::size_t i = 0; i < back.size(); ++i)
      worst = std::max(worst, std::abs(back[i] - level0[i]));
    return worst / ulp;
  };
  lod.inverse(0);  // level 1 -> level 0
  const float one = worst_ulp(lod.read(0));
  for (int k = 2; k >= 0; --k) lod.inverse(k);  // level 3 -> 2 -> 1 -> 0
  const float three = worst_ulp(lod.read(0));
  std::cout << "Haar round trip: one level " << one << " ulp, three levels " << three << " ulp\n";
  EXPECT_LE(one, 3.0f);
  EXPECT_LE(three, 9.0f);
}

// 002 §4.3 draws each level from its texture, never read back (HaarLod::grid). The expected
// silhouette is the same level read back to the host and drawn from a vertex buffer (002 §4.1):
// the same points and triangles through the other vertex path, so the two images agree pixel for
// pixel up to rasterization ties; a wrong origin, size or level would move or resize the surface.
TEST(GlslDeBoorLod, LevelsDrawnFromTheDeviceCoverTheirReadBackSilhouette) {
  if (!gl::Context::probe(gl::Platform::egl).available) GTEST_SKIP();
  auto context = gl::Context::create(gl::Platform::egl);
  const Scene scene = *make_builtin_scene("tan21x23");
  Sampling grid;
  grid.grid_u = 128;
  grid.grid_v = 64;
  Evaluator evaluator(*context, context->max_texture_size());
  evaluator.prepare(scene, sample_parameters(scene, grid));
  evaluator.evaluate();
  HaarLod lod(*context, evaluator.pages()[0], evaluator.pages()[0].slots[0], 3);
  for (int k = 0; k < 3; ++k) lod.forward(k);
  gl::GridRenderer renderer(*context, 256, 256);
  const std::array<float, 16> view = gl::orthographic_view(scene);
  auto drawn = [](const std::vector<unsigned char>& image) {
    long n = 0;
    for (std::size_t i = 3; i < image.size(); i += 4) n += image[i] != 0;
    return n;
  };
  long previous = 0;
  for (int k = 0; k <= 3; ++k) {
    SCOPED_TRACE(k);
    const gl::GridPoints points = lod.grid(k);
    EXPECT_EQ(points.nu, 128 >> k);
    EXPECT_EQ(points.nv, 64 >> k);
    renderer.begin_frame();
    renderer.draw(points, view.data(), nullptr);
    renderer.end_frame("lod test, from the device");
    const std::vector<unsigned char> device = renderer.image();
    const std::vector<float> xyz = k == 0 ? evaluator.read_back()[0] : lod.read(k);
    renderer.begin_frame();
    renderer.draw(xyz.data(), points.nu, points.nv, view.data(), nullptr);
    renderer.end_frame("lod test, from the host");
    const std::vector<unsigned char> host = renderer.image();
    ASSERT_EQ(device.size(), host.size());
    long covered_differently = 0;
    for (std::size_t i = 3; i < host.size(); i += 4)
      covered_differently += (device[i] != 0) != (host[i] != 0);
    const long pixels = drawn(device);
    // A quarter of the 256² image at least: the view fits the control net in 90% of it.
    EXPECT_GT(pixels, 256 * 256 / 4);
    EXPECT_LE(covered_differently, pixels / 1000) << pixels;
    // Coarser levels' averages pull the boundary inward: each covers no more than the finer one.
    if (k > 0) {
      EXPECT_LE(pixels, previous);
    }
    previous = pixels;
  }
}

// The index buffers the LOD baseline rebuilds at each change of size: two triangles per cell.
TEST(GlslDeBoorLod, RebuiltIndexBufferHasTwoTrianglesPerCell) {
  if (!gl::Context::probe(gl::Platform::egl).available) GTEST_SKIP();
  auto context = gl::Context::create(gl::Platform::egl);
  gl::GridRenderer renderer(*context, 16, 16);
  for (auto [nu, nv] : {std::pair{2, 2}, {16, 8}, {128, 128}, {3, 1024}})
    EXPECT_EQ(renderer.rebuild_index_buffer(nu, nv), (nu - 1) * (nv - 1) * 6) << nu << "x" << nv;
  // Cell (0, 0) of a 3 x 2 grid: vertices 0, 1 (row b = 0) and 3, 4 (row b = 1).
  const std::vector<GLuint> cells = gl::grid_triangle_indices(3, 2);
  ASSERT_EQ(cells.size(), 12u);
  EXPECT_EQ(std::vector<GLuint>(cells.begin(), cells.begin() + 6),
            (std::vector<GLuint>{0, 1, 4, 0, 4, 3}));
}

// `nurbsbench lod` (002 Fig 15). The level distances follow from the averaging alone: a level-k
// value averages a block of n = 2^k equally spaced samples (spacing d) per direction, and on a
// smooth surface the average departs from the point at the block's mean parameter by
// (1/2) S'' var, var = (n^2 - 1) d^2 / 12 per direction: 0.25 d^2 at level 1, 1.25 d^2 at level 2,
// so level 2 lies 5x as far from the surface as level 1, up to higher-order terms.
TEST(GlslDeBoorLod, LodVerbWritesFig15RowsWithSecondOrderLevelDistances) {
  if (!gl::Context::probe(gl::Platform::egl).available) GTEST_SKIP();
  const test::TempDir tmp;
  const std::string out = tmp / "lod";
  const test::CliResult r = test::run_cli(
      {"lod", "--samples", "64x64,256x256", "--levels", "2", "--repetitions", "2", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("002 Fig 15"), std::string::npos) << r.out;
  const nlohmann::json doc =
      nlohmann::json::parse(test::read_text(std::filesystem::path(out) / "lod.json"));
  EXPECT_EQ(doc["format"], "nurbsbench-lod/1");
  ASSERT_EQ(doc["rows"].size(), 2u);
  for (const nlohmann::json& row : doc["rows"]) {
    EXPECT_EQ(row["scene"], "tan21x23");
    EXPECT_EQ(row["device"]["kind"], "cpu");  // llvmpipe
    for (const char* key :
         {"coarser_by_haar_s", "coarser_by_reevaluation_s", "coarser_by_full_reevaluation_s",
          "finer_by_haar_s", "finer_by_reevaluation_s", "finer_by_full_reevaluation_s", "render_s"})
      EXPECT_GT(row[key].get<double>(), 0.0) << key;
    const int n = std::stoi(row["samples"].get<std::string>());  // square grids here
    EXPECT_EQ(row["finer_index_elements"], (n - 1) * (n - 1) * 6);
    EXPECT_EQ(row["coarser_index_elements"], (n / 2 - 1) * (n / 2 - 1) * 6);
    EXPECT_EQ(row["index_elements"], (n - 1) * (n - 1) * 6);
    const long full_grid = row["drawn_pixels"].get<long>();
    EXPECT_GT(full_grid, 0);
    ASSERT_EQ(row["levels"].size(), 2u);
    for (const nlohmann::json& level : row["levels"]) {
      SCOPED_TRACE(level.dump());
      const int m = n >> level["level"].get<int>();
      EXPECT_EQ(level["samples"], fmt::format("{}x{}", m, m));
      EXPECT_EQ(level["index_elements"], (m - 1) * (m - 1) * 6);
      EXPECT_GT(level["render_s"].get<double>(), 0.0);
      // A coarser level of the same surface covers most of the full grid's pixels, and no more
      // (averages pull the boundary inward); half would mean geometry drawn wrong.
      EXPECT_GT(level["drawn_pixels"].get<long>(), full_grid / 2);
      EXPECT_LE(level["drawn_pixels"].get<long>(), full_grid);
    }
  }
  const nlohmann::json& levels = doc["rows"][1]["levels"];
  EXPECT_EQ(levels[0]["samples"], "128x128");
  EXPECT_EQ(levels[1]["samples"], "64x64");
  const double ratio =
      levels[1]["max_distance"].get<double>() / levels[0]["max_distance"].get<double>();
  EXPECT_GT(ratio, 4.3);
  EXPECT_LT(ratio, 5.5);
  // 256 samples over a surface ~10 wide: d ~ 0.04, level-1 offsets ~1e-3, far above float noise.
  EXPECT_GT(levels[0]["max_distance"].get<double>(), 1e-4);
  EXPECT_LT(levels[0]["max_distance"].get<double>(), 1e-2);
}

// `lod --images DIR`: every level of every grid as drawn, one PNG each (a build without
// OpenImageIO refuses the option before measuring).
TEST(GlslDeBoorLod, LodImagesWritesEveryLevelAsDrawn) {
  if (!gl::Context::probe(gl::Platform::egl).available) GTEST_SKIP();
  const test::TempDir tmp;
  const std::string out = tmp / "lod", images = tmp / "images";
  const test::CliResult r = test::run_cli({"lod", "--samples", "64x64", "--levels", "2",
                                           "--repetitions", "1", "--out", out, "--images", images});
  if (r.exit_code != 0 && r.err.find("no OpenImageIO") != std::string::npos) GTEST_SKIP() << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (int level = 0; level <= 2; ++level) {
    const std::filesystem::path png =
        std::filesystem::path(images) / fmt::format("lod__tan21x23__64x64__L{}.png", level);
    ASSERT_TRUE(std::filesystem::exists(png)) << png;
    EXPECT_EQ(test::read_text(png).substr(0, 4), "\x89PNG") << png;
  }
}

}  // namespace
}  // namespace nurbs::glsl_deboor
