// 002 §4.3: Haar-wavelet levels of the evaluated tan21x23 surface (the paper's Fig 15 net). The
// forward + inverse round trip is not bit-for-bit: A = (a0 + a1) / 2, D = (a0 - a1) / 2 and A + D
// each round once (the halving is exact), so one 1D step returns a0 within 1.5 ulp of the
// largest coordinate and one level (row + column step) within 3; three levels within 9. Level 1
// is the 2x2 averages of level 0 (row step, then column step). Fig 15's timings and each level's
// distance to the surface: `nurbsbench lod` (tested at the end).
#include <gtest/gtest.h>

#include <algorithm>
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
    for (const char* key : {"coarser_by_haar_s", "coarser_by_reevaluation_s", "finer_by_haar_s",
                            "finer_by_reevaluation_s"})
      EXPECT_GT(row[key].get<double>(), 0.0) << key;
    ASSERT_EQ(row["levels"].size(), 2u);
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

}  // namespace
}  // namespace nurbs::glsl_deboor
