// The memory table (RPNS Table 1): counts checked against hand counts and against the actual
// decomposition's output.
#include "harness/memory_table.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "reference/bezier_decomposition.h"
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
  EXPECT_DOUBLE_EQ(teapot.ratio(), 1.0);
  // patch144: bicubic, 12x12 points, 8 distinct interior knots a side: 9 x 9 spans of 16 points.
  const MemoryRow patch = memory_row(*make_builtin_scene("patch144"));
  EXPECT_EQ(patch.ksquads, 81u);
  EXPECT_EQ(patch.nurbs_control_points, 144u);
  EXPECT_EQ(patch.bezier_control_points, 81u * 16);
  EXPECT_EQ(patch.nurbs_bytes(), 144u * 16);
  EXPECT_EQ(patch.bezier_bytes(), 81u * 16 * 16);
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
}

}  // namespace
}  // namespace nurbs
