// `nurbsbench camera-path` (000 §3.2 continuous LOD along a fly-in) driven as a user would, tiny:
// every recorded grid is recomputed here from the recorded camera by the rule written out
// independently (projection by the textbook look-at and perspective formulas), the triangles from
// the grids, and the context's counters say the timed frames read nothing back to the host. Then
// `report` draws its chart from the file alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <numbers>

#include "run_cli.h"
#include "scenes/builtin_scenes.h"

namespace nurbs::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using V = std::array<double, 3>;

V minus(const V& a, const V& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const V& a, const V& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
V normalized(const V& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}
V cross(const V& a, const V& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
V vec(const json& j) {
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

// gluLookAt + gluPerspective, then the viewport transform: p's pixel position.
std::array<double, 2> pixel_of(const V& p, const V& eye, const V& target, const V& up,
                               double fov_y_degrees, int width, int height) {
  const V f = normalized(minus(target, eye));
  const V s = normalized(cross(f, up));
  const V u = cross(s, f);
  const V d = minus(p, eye);
  const double xe = dot(s, d), ye = dot(u, d), ze = -dot(f, d);
  EXPECT_LT(ze, 0) << "a control point behind the eye";
  const double cot = 1 / std::tan(fov_y_degrees / 2 * std::numbers::pi / 180);
  const double aspect = double(width) / height;
  return {(cot / aspect * xe / -ze + 1) / 2 * width, (cot * ye / -ze + 1) / 2 * height};
}

// The rule of 000 §3.2 as camera_lod.h states it, written out again: per direction the longest
// projected control polygon, one sample per `pps` pixels plus one, clamped.
std::pair<int, int> expected_grid(const Surface& s, const V& eye, const V& target, const V& up,
                                  double fov, int width, int height, double pps, int lo, int hi) {
  auto px = [&](int i, int j) {
    return pixel_of(s.point(i, j), eye, target, up, fov, width, height);
  };
  auto dist = [](const std::array<double, 2>& a, const std::array<double, 2>& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]));
  };
  double lu = 0, lv = 0;
  for (int j = 0; j < s.count_v; ++j) {
    double sum = 0;
    for (int i = 1; i < s.count_u; ++i) sum += dist(px(i - 1, j), px(i, j));
    lu = std::max(lu, sum);
  }
  for (int i = 0; i < s.count_u; ++i) {
    double sum = 0;
    for (int j = 1; j < s.count_v; ++j) sum += dist(px(i, j - 1), px(i, j));
    lv = std::max(lv, sum);
  }
  auto n = [&](double length) {
    return std::clamp(static_cast<int>(std::ceil(length / pps)) + 1, lo, hi);
  };
  return {n(lu), n(lv)};
}

TEST(CliCameraPath, GridsFollowTheProjectedSizeAndFramesReadNothingBack) {
  TempDir tmp;
  const std::string out = tmp / "camera";
  const int frames = 4, width = 80, height = 60;
  const CliResult r =
      run_cli({"camera-path", "--scenes", "teapot", "--frames", std::to_string(frames),
               "--viewport", "80x60", "--pixels-per-sample", "2", "--min-samples", "3",
               "--max-samples", "40", "--fixed-samples", "6x5", "--out", out});
  if (r.exit_code == 2 && r.err.find("unavailable") != std::string::npos) GTEST_SKIP() << r.err;
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("000 §3.2"), std::string::npos) << r.out;
  const json doc = json::parse(read_text(fs::path(out) / "camera_path.json"));
  EXPECT_EQ(doc["format"], "nurbsbench-camera-path/1");
  const json& settings = doc["settings"];
  EXPECT_EQ(settings["frames"], frames);
  EXPECT_EQ(settings["viewport"], "80x60");
  const double fov = settings["fov_y_degrees"].get<double>();
  ASSERT_EQ(doc["rows"].size(), 1u);
  const json& row = doc["rows"][0];
  const Scene scene = *make_builtin_scene("teapot");
  ASSERT_EQ(row["surfaces"], scene.surfaces.size());
  if (row["device"]["name"].get<std::string>().find("llvmpipe") != std::string::npos) {
    EXPECT_EQ(row["device"]["kind"], "cpu");
    EXPECT_NE(r.out.find("CPU figures"), std::string::npos) << r.out;
  }
  const V target = vec(row["target"]), up = vec(row["up"]);
  ASSERT_EQ(row["frames"].size(), static_cast<std::size_t>(frames));
  bool between = false, unequal = false;
  double previous_distance = INFINITY;
  std::uint64_t first_samples = 0, last_samples = 0;
  for (const json& frame : row["frames"]) {
    SCOPED_TRACE(frame["frame"].dump());
    const V eye = vec(frame["eye"]);
    const double distance = frame["distance"].get<double>();
    EXPECT_LT(distance, previous_distance);  // flying in
    EXPECT_NEAR(std::sqrt(dot(minus(eye, target), minus(eye, target))), distance, 1e-9 * distance);
    previous_distance = distance;
    std::uint64_t samples = 0, triangles = 0;
    ASSERT_EQ(frame["lod_grids"].size(), scene.surfaces.size());
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const auto [nu, nv] =
          expected_grid(scene.surfaces[i], eye, target, up, fov, width, height, 2, 3, 40);
      EXPECT_EQ(frame["lod_grids"][i][0], nu) << "surface " << i;
      EXPECT_EQ(frame["lod_grids"][i][1], nv) << "surface " << i;
      between = between || (nu > 3 && nu < 40);
      unequal = unequal || nu != nv;
      samples += static_cast<std::uint64_t>(nu) * nv;
      triangles += 2ull * (nu - 1) * (nv - 1);
    }
    EXPECT_EQ(frame["lod_samples"], samples);
    EXPECT_EQ(frame["lod_triangles"], triangles);
    EXPECT_EQ(frame["fixed_triangles"], scene.surfaces.size() * 2 * 5 * 4);
    EXPECT_GT(frame["lod_frame_s"].get<double>(), 0);
    EXPECT_GT(frame["fixed_frame_s"].get<double>(), 0);
    if (frame["frame"] == 0) first_samples = samples;
    last_samples = samples;
  }
  // The rule is exercised: grids grow as the camera closes in, inside the clamp, unequal in u, v.
  EXPECT_GT(last_samples, first_samples);
  EXPECT_TRUE(between);
  EXPECT_TRUE(unequal);
  // 000 §3.2: drawn from a device copy, never read back, in both timed paths.
  for (const char* counts : {"lod_counts", "fixed_counts"}) {
    SCOPED_TRACE(counts);
    EXPECT_EQ(row[counts]["host_read_backs"], 0);
    EXPECT_EQ(row[counts]["device_copies"], frames * scene.surfaces.size());
  }

  // The report reads camera_path.json alone and draws frame time and triangles per frame.
  const CliResult report = run_cli({"report", "--results", out, "--out", tmp / "report"});
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const json charts = json::parse(read_text(tmp.path() / "report/charts.json"));
  const auto chart = std::find_if(charts["charts"].begin(), charts["charts"].end(),
                                  [](const json& c) { return c["id"] == "camera_path"; });
  ASSERT_NE(chart, charts["charts"].end());
  ASSERT_EQ((*chart)["series"].size(), 4u);
  for (const json& series : (*chart)["series"]) {
    EXPECT_EQ(series["x"].size(), static_cast<std::size_t>(frames)) << series["label"];
    EXPECT_EQ(series.value("axis", "") == "y2",
              series["label"].get<std::string>().starts_with("triangles"))
        << series["label"];
  }
  EXPECT_NE(read_text(tmp.path() / "report/REPORT.md").find("continuous LOD"), std::string::npos);
}

}  // namespace
}  // namespace nurbs::test
