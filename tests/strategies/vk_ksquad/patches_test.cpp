// vk-ksquad's patch cutting and tessellator vertex counts, on the CPU (every build).
#include "strategies/vk_ksquad/patches.h"

#include <gtest/gtest.h>

#include <limits>

namespace nurbs::vk_ksquad {
namespace {

TEST(SplitRun, ShortRunIsOnePatch) {
  const auto pieces = split_run({5, 10, 17}, 64);
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0].begin, 10);
  EXPECT_EQ(pieces[0].count, 17);
  EXPECT_EQ(run_level(pieces[0]), 16);
}

TEST(SplitRun, LongRunIsCutIntoPiecesSharingTheirEnds) {
  // 201 samples = 200 segments > 64: four pieces of 50 segments, each within the cap.
  const auto pieces = split_run({3, 0, 201}, 64);
  ASSERT_EQ(pieces.size(), 4u);
  int expected_begin = 0;
  for (const auto& p : pieces) {
    EXPECT_EQ(p.span, 3);
    EXPECT_EQ(p.begin, expected_begin);
    EXPECT_LE(run_level(p), 64);
    expected_begin = p.begin + p.count - 1;  // the next piece starts on this one's last sample
  }
  EXPECT_EQ(expected_begin, 200);  // every sample covered, none clamped away
}

TEST(SplitRun, ExactlyTheCapIsOnePatch) {
  EXPECT_EQ(split_run({0, 0, 65}, 64).size(), 1u);
  EXPECT_EQ(split_run({0, 0, 66}, 64).size(), 2u);
}

TEST(SplitRun, NoCapIsOnePatch) {
  EXPECT_EQ(split_run({0, 0, 1000}, std::numeric_limits<int>::max()).size(), 1u);
}

TEST(SplitRun, SingleSampleIsOnePatchOfLevelOne) {
  const auto pieces = split_run({2, 7, 1}, 64);
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(run_level(pieces[0]), 1);
}

TEST(QuadDomainVertices, UniformLevelsGiveTheLattice) {
  for (int t = 1; t <= 64; ++t)
    EXPECT_EQ(quad_domain_vertices(t, t), static_cast<std::uint64_t>((t + 1) * (t + 1))) << t;
  EXPECT_EQ(quad_domain_vertices(3, 5), 24u);  // 4 x 6 lattice
}

TEST(QuadDomainVertices, InnerLevelOneIsRaisedToTwo) {
  // Outer ring 2*1 + 2*4 = 10 vertices, inner levels (2, 4): 1 x 3 inside.
  EXPECT_EQ(quad_domain_vertices(1, 4), 13u);
}

}  // namespace
}  // namespace nurbs::vk_ksquad
