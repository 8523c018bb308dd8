// The memory table (RPNS Table 1): counts checked against hand counts and against the actual
// decomposition's output.
#include "harness/memory_table.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <set>
#include <vector>

#include "reference/bezier_decomposition.h"
#include "reference/tspline.h"
#include "reference/tspline_extraction.h"
#include "scenes/builtin_scenes.h"

namespace nurbs {
namespace {

TEST(MemoryTable, HandCountedScenes) {
  // teapot: 32 bicubic Bézier patches, nothing to insert.
  const MemoryRow teapot = memory_row(*make_builtin_scene("teapot"));
  EXPECT_EQ(teapot.surfaces, 32u);
  EXPECT_EQ(teapot.ksquads, 32u);
  EXPECT_EQ(teapot.nurbs_control_points, 32u * 16);
  EXPECT_EQ(teapot.bezier_control_points, 32u * 16);
  EXPECT_EQ(teapot.bezier_shared_control_points, 32u * 16);  // one patch a surface: none shared
  EXPECT_DOUBLE_EQ(teapot.ratio(), 1.0);
  // patch144: bicubic, 12x12 points, 8 distinct interior knots a side: 9 x 9 spans of 16 points.
  const MemoryRow patch = memory_row(*make_builtin_scene("patch144"));
  EXPECT_EQ(patch.ksquads, 81u);
  EXPECT_EQ(patch.nurbs_control_points, 144u);
  EXPECT_EQ(patch.bezier_control_points, 81u * 16);
  EXPECT_EQ(patch.nurbs_bytes(), 144u * 16);
  EXPECT_EQ(patch.bezier_bytes(), 81u * 16 * 16);
  // 9 patches of 4 points a side sharing 8 boundary rows: 28 points a side.
  EXPECT_EQ(patch.bezier_shared_control_points, 28u * 28);
  EXPECT_EQ(patch.bezier_shared_bytes(), 28u * 28 * 16);
  EXPECT_DOUBLE_EQ(patch.shared_ratio(), 784.0 / 144);
}

// Non-empty spans from the knot values alone: the distinct knots of the domain
// [knots[p], knots[count]] bound one span fewer than their number.
std::size_t spans_from_knots(int degree, int count, const std::vector<double>& knots) {
  std::set<double> distinct(knots.begin() + degree, knots.begin() + count + 1);
  return distinct.size() - 1;
}

TEST(MemoryTable, SharedCountFromTheKnotVectors) {
  for (const char* name :
       {"duck", "creases", "clustered", "degree-7", "tan21x23", "sphere", "torus", "hammer"}) {
    const Scene scene = *make_builtin_scene(name);
    std::size_t shared = 0, per_patch = 0;
    for (const Surface& s : scene.surfaces) {
      const std::size_t su = spans_from_knots(s.degree_u, s.count_u, s.knots_u);
      const std::size_t sv = spans_from_knots(s.degree_v, s.count_v, s.knots_v);
      const std::size_t p = s.degree_u, q = s.degree_v;
      shared += (su * p + 1) * (sv * q + 1);
      per_patch += su * sv * (p + 1) * (q + 1);
    }
    const MemoryRow row = memory_row(scene);
    EXPECT_EQ(row.bezier_shared_control_points, shared) << name;
    EXPECT_EQ(row.bezier_control_points, per_patch) << name;
    EXPECT_LE(row.bezier_shared_control_points, row.bezier_control_points) << name;
  }
  // creases: full-multiplicity interior knots already split it into patches; shared-once holds
  // exactly the NURBS net.
  const MemoryRow creases = memory_row(*make_builtin_scene("creases"));
  EXPECT_EQ(creases.bezier_shared_control_points, creases.nurbs_control_points);
}

TEST(MemoryTable, BezierCountIsWhatTheDecompositionProduces) {
  for (const char* name : {"duck", "creases", "degree-7", "tan21x23", "many-5", "sphere"}) {
    const Scene scene = *make_builtin_scene(name);
    std::size_t points = 0, patches = 0;
    for (const Surface& s : scene.surfaces) {
      const BezierPatches<double> b = decompose_surface(SurfaceNet<double>(s));
      points += b.points.size();
      patches += b.patch_count();
    }
    const MemoryRow row = memory_row(scene);
    EXPECT_EQ(row.bezier_control_points, points) << name;
    EXPECT_EQ(row.ksquads, patches) << name;
    EXPECT_EQ(row.nurbs_control_points, scene.control_point_count()) << name;
  }
}

TEST(MemoryTable, JsonCarriesEveryColumnAndTheUnits) {
  const nlohmann::json j = memory_table_json({memory_row(*make_builtin_scene("patch144"))});
  EXPECT_EQ(j["format"], "nurbsbench-memory/1");
  EXPECT_EQ(j["bytes_per_control_point"], 16);
  ASSERT_EQ(j["rows"].size(), 1u);
  const nlohmann::json& row = j["rows"][0];
  EXPECT_EQ(row["scene"], "patch144");
  EXPECT_EQ(row["ksquads"], 81);
  EXPECT_EQ(row["bezier_control_points"], 1296);
  EXPECT_EQ(row["nurbs_bytes"], 2304);
  EXPECT_EQ(row["bezier_bytes"], 20736);
  EXPECT_DOUBLE_EQ(row["ratio"].get<double>(), 9.0);
  EXPECT_EQ(row["bezier_shared_control_points"], 784);
  EXPECT_EQ(row["bezier_shared_bytes"], 784 * 16);
  EXPECT_DOUBLE_EQ(row["shared_ratio"].get<double>(), 784.0 / 144);
}

}  // namespace
}  // namespace nurbs

namespace nurbs {
namespace {

// A T-spline's row: its own control points, and its Bézier extraction's patches. tspline-refined
// is tan21x23 (18 x 20 spans) with three new knot columns, so 21 x 20 cells.
TEST(MemoryTable, TSplineRowIsItsBezierExtraction) {
  const Scene scene = *make_builtin_scene("tspline-refined");
  const MemoryRow row = memory_row(scene);
  const TSplineSurface& t = *scene.surfaces[0].tspline;
  const TSplineExtraction extraction = extract_bezier_elements(t, TSplineInfluence(t, "t"));
  EXPECT_EQ(extraction.elements.size(), 21u * 20u);
  EXPECT_EQ(row.ksquads, extraction.elements.size());
  EXPECT_EQ(row.nurbs_control_points, 21u * 23u + 6u);
  EXPECT_EQ(row.bezier_control_points, 21u * 20u * 16u);
  EXPECT_EQ(row.bezier_shared_control_points, (21u * 3 + 1) * (20u * 3 + 1));
}

}  // namespace
}  // namespace nurbs
