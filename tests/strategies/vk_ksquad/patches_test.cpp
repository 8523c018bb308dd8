// vk-ksquad's patch cutting and tessellator vertex counts, on the CPU (every build).
#include "strategies/vk_ksquad/patches.h"

#include <gtest/gtest.h>

#include <limits>

#include "reference/sampling.h"
#include "scenes/builtin_scenes.h"

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

// A grid coarser than the knots (tan256: 253 spans, 64 samples): every non-empty span gets a
// run, in order; the runs holding samples are kept as they were and every sample is in one.
TEST(WithEmptySpans, EveryNonEmptySpanOnceInOrder) {
  const Surface s = make_builtin_scene("tan256")->surfaces[0];
  const std::vector<double> u = grid_parameters(s.u_min(), s.u_max(), 64);
  const std::vector<float> k32(s.knots_u.begin(), s.knots_u.end());
  const auto runs = ksquad::runs_of_grid(u, s.degree_u, s.count_u, k32);
  const auto all = with_empty_spans(runs, s.knots_u, s.degree_u, s.count_u);
  std::vector<int> spans;
  for (int i = s.degree_u; i < s.count_u; ++i)
    if (s.knots_u[i] < s.knots_u[i + 1]) spans.push_back(i);
  ASSERT_EQ(all.size(), spans.size());
  std::size_t kept = 0;
  int samples = 0;
  for (std::size_t k = 0; k < all.size(); ++k) {
    EXPECT_EQ(all[k].span, spans[k]);
    if (all[k].count == 0) {
      EXPECT_EQ(run_level(all[k]), 0);
      continue;
    }
    ASSERT_LT(kept, runs.size());
    EXPECT_EQ(all[k].begin, runs[kept].begin);
    EXPECT_EQ(all[k].count, runs[kept].count);
    samples += all[k].count;
    ++kept;
  }
  EXPECT_EQ(kept, runs.size());
  EXPECT_EQ(samples, 64);
}

TEST(PieceShare, PiecesTileTheSpan) {
  const ksquad::SpanRun run{4, 10, 101};
  const auto pieces = split_run(run, 64);
  ASSERT_EQ(pieces.size(), 2u);
  EXPECT_EQ(piece_share(run, pieces[0]).first, 0.0f);
  EXPECT_EQ(piece_share(run, pieces[0]).second, piece_share(run, pieces[1]).first);
  EXPECT_EQ(piece_share(run, pieces[0]).second, 0.5f);
  EXPECT_EQ(piece_share(run, pieces[1]).second, 1.0f);
  EXPECT_EQ(piece_share({4, 10, 1}, {4, 10, 1}), std::make_pair(0.0f, 1.0f));
}

}  // namespace
}  // namespace nurbs::vk_ksquad
