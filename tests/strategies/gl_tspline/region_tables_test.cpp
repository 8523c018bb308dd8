// gl-tspline's CPU tables (strategies/gl_tspline/region_tables.h), without GL: the CSR lists hold
// exactly the influence index's points with the spans the reference evaluates them on, samples
// carry the region the reference's binary searches find, and the pass count is the ceiling.
#include "strategies/gl_tspline/region_tables.h"

#include <gtest/gtest.h>

#include "reference/tmesh.h"
#include "tests/reference/random_nurbs.h"
#include "tests/tspline/tspline_meshes.h"

namespace nurbs::gl_tspline {
namespace {

TEST(GlTSplineTables, RegionListsAreTheInfluenceIndexWithSpans) {
  test::Rng rng(51);
  for (const TMesh& mesh : test::random_vertical_tmeshes(rng, {{3, 3}, {5, 1}}, 3, true)) {
    const TSplineSurface ts = infer_tspline(mesh, "test");
    const TSplineInfluence index(ts, "test");
    const RegionTables t = make_region_tables(ts, index);
    ASSERT_EQ(t.regions, static_cast<std::size_t>(index.cells_u() * index.cells_v()));
    ASSERT_EQ(t.offsets.size() % kLinearWidth, 0u);
    ASSERT_EQ(t.active.size() % (4 * kLinearWidth), 0u);
    int most = 0;
    for (int cu = 0; cu < index.cells_u(); ++cu)
      for (int cv = 0; cv < index.cells_v(); ++cv) {
        const std::size_t r = static_cast<std::size_t>(cu * index.cells_v() + cv);
        const int* first = index.active_begin(cu, cv);
        const int count = static_cast<int>(index.active_end(cu, cv) - first);
        ASSERT_EQ(t.offsets[r + 1] - t.offsets[r], count) << "region " << r;
        most = std::max(most, count);
        // Each cell lies inside every listed support: the span holding its centre is the one.
        const double mu = (index.breaks_u()[cu] + index.breaks_u()[cu + 1]) / 2;
        const double mv = (index.breaks_v()[cv] + index.breaks_v()[cv + 1]) / 2;
        for (int i = 0; i < count; ++i) {
          const std::int32_t* e = &t.active[4 * static_cast<std::size_t>(t.offsets[r] + i)];
          EXPECT_EQ(e[0], first[i]);
          EXPECT_EQ(e[1], local_span(ts.degree_u, ts.local_knots_u(first[i]), mu, false));
          EXPECT_EQ(e[2], local_span(ts.degree_v, ts.local_knots_v(first[i]), mv, false));
        }
      }
    EXPECT_EQ(t.max_active, most);
    for (std::size_t k = 0; k < ts.count(); ++k) {
      EXPECT_EQ(t.homogeneous[4 * k + 3], static_cast<float>(ts.weights[k]));
      EXPECT_EQ(t.homogeneous[4 * k], static_cast<float>(ts.points[k][0] * ts.weights[k]));
    }
  }
}

TEST(GlTSplineTables, SamplesCarryTheirRegion) {
  test::Rng rng(52);
  const TSplineSurface ts = infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 8, 7, false), "t");
  const TSplineInfluence index(ts, "t");
  SurfaceSamples samples;
  samples.u = grid_parameters(ts.u_min, ts.u_max, 1500);  // more than one row of kLinearWidth
  samples.v = grid_parameters(ts.v_min, ts.v_max, 3);
  const SampleTable t = make_sample_table(index, samples);
  ASSERT_EQ(t.count, 4500u);
  ASSERT_EQ(t.width, kLinearWidth);
  ASSERT_EQ(t.height, 5);
  for (std::size_t k = 0; k < static_cast<std::size_t>(t.width) * t.height; ++k) {
    const std::size_t s = k < t.count ? k : 0;  // padding repeats sample 0
    const double u = samples.u_of(s), v = samples.v_of(s);
    EXPECT_EQ(t.uv[2 * k], static_cast<float>(u));
    EXPECT_EQ(t.uv[2 * k + 1], static_cast<float>(v));
    EXPECT_EQ(t.regions[k], index.cell_u(u) * index.cells_v() + index.cell_v(v)) << k;
  }
}

TEST(GlTSplineTables, AccumulationPassesCoverTheLargestRegion) {
  EXPECT_EQ(accumulation_passes(16, 16), 1);
  EXPECT_EQ(accumulation_passes(17, 16), 2);
  EXPECT_EQ(accumulation_passes(16, 1), 16);
  EXPECT_EQ(accumulation_passes(20, 3), 7);
  EXPECT_EQ(linear_rows(0), 1);
  EXPECT_EQ(linear_rows(kLinearWidth), 1);
  EXPECT_EQ(linear_rows(kLinearWidth + 1), 2);
}

}  // namespace
}  // namespace nurbs::gl_tspline
