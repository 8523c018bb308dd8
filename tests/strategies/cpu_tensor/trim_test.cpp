// cpu-tensor trims: its row classifier (strategies/cpu_tensor/row_trim.h) against closed forms
// (the built-in trimmed-plate's face, polygons whose vertices and edges lie on sample rows and
// columns), and the gate of issue 15: no sample outside the band misclassified against the
// reference's exact classification, on trimmed-plate and the hammer, grid and span grid, f32 and
// f64, scored by the harness as a run scores it.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/cpu_tensor/row_trim.h"
#include "strategies/registry.h"
#include "tests/harness/plates.h"
#include "tests/reference/test_support.h"
#include "tests/scenes/trimmed_plate_closed_form.h"

namespace nurbs {
namespace {

using test::grid;
using test::span_grid;

using test::bilinear_patch;
using test::expect_mask_is_the_closed_form;
using test::trimmed_plate_signed_distance;

std::unique_ptr<Strategy> tensor(int threads) {
  StrategyOptions options;
  options.threads = threads;
  return find_strategy("cpu-tensor")->create(options);
}

// The masks of every surface after evaluate() and classify().
std::vector<std::vector<std::uint8_t>> masks(const Scene& scene, const EvalRequest& request,
                                             int threads) {
  auto strategy = tensor(threads);
  strategy->prepare(scene, request);
  strategy->evaluate();
  EXPECT_TRUE(strategy->classify());
  std::vector<std::vector<std::uint8_t>> out;
  for (const SurfaceResult& r : strategy->read_back().surfaces) out.push_back(r.inside);
  return out;
}

// cpu-tensor intersects the lines u = const, the reference v = const: a face not symmetric in
// u <-> v (the hole off the diagonal) tells a mirrored answer from the right one.
TrimmedPlateShape asymmetric_shape() {
  TrimmedPlateShape shape;
  shape.hole_center_u = 0.42;
  shape.hole_center_v = 0.57;
  return shape;
}

TEST(CpuTensorTrim, MaskIsTheFacesClosedForm) {
  const TrimmedPlateShape shape = asymmetric_shape();
  Scene scene = trimmed_plate_scene(shape);
  scene.surfaces.push_back(scene.surfaces[0]);  // the same plate untrimmed: no mask
  scene.surfaces[1].trim.reset();
  ASSERT_TRUE(find_strategy("cpu-tensor")->capabilities().trims);
  // 64 x 47: k/63, j/46, no sample on the frame's straight sides; span8 on the plate's spans.
  for (const Sampling& sampling : {grid(64, 47), span_grid(8)})
    for (Precision precision : {Precision::f32, Precision::f64}) {
      const EvalRequest request{sampling, precision, false};
      auto strategy = tensor(2);
      strategy->prepare(scene, request);
      strategy->evaluate();
      EXPECT_TRUE(strategy->read_back().surfaces[0].inside.empty()) << "no mask before classify()";
      ASSERT_TRUE(strategy->classify());
      const EvalResult result = strategy->read_back();
      const SurfaceResult& r = result.surfaces[0];
      ASSERT_EQ(r.inside.size(), r.samples.count());
      EXPECT_TRUE(result.surfaces[1].inside.empty());
      SCOPED_TRACE(sampling.label());
      const auto [inside, checked] = expect_mask_is_the_closed_form(shape, r.samples, r.inside);
      EXPECT_GT(checked, r.samples.count() * 9 / 10);
      // A uniform grid's inside share is about the face's area: the mask is not one answer.
      if (sampling.mode == SamplingMode::grid) {
        EXPECT_NEAR(static_cast<double>(inside) / checked, shape.inside_area(), 0.05);
      }
      // Rows are independent: any thread count gives the same mask.
      EXPECT_EQ(masks(scene, request, 1)[0], r.inside) << sampling.label();
      EXPECT_EQ(masks(scene, request, 3)[0], r.inside) << sampling.label();

      strategy->prepare(scene, request);
      EXPECT_TRUE(strategy->read_back().surfaces[0].inside.empty()) << "prepare() starts over";
    }
}

TrimLoop polygon(const std::vector<Point2>& corners) {
  TrimLoop loop;
  for (std::size_t k = 0; k < corners.size(); ++k)
    loop.curves.push_back(test::trim_line(corners[k], corners[(k + 1) % corners.size()]));
  return loop;
}

// A unit plate trimmed by `loops`, sampled on the 11 x 11 grid u, v = k/10: its rows (u = const,
// the lines cpu-tensor intersects) and columns pass through the polygons' vertices and along
// their edges, where counting a vertex twice or an edge as a crossing flips whole stretches.
std::vector<std::uint8_t> plate_mask(std::vector<TrimLoop> loops, const EvalRequest& request) {
  Surface s = bilinear_patch("plate", {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0});
  Trim trim;
  trim.loops = std::move(loops);
  s.trim = trim;
  return masks(Scene{"polygon-plate", "", {s}}, request, 2)[0];
}

void expect_mask(const std::vector<TrimLoop>& loops,
                 const std::function<double(double, double)>& signed_distance) {
  for (Precision precision : {Precision::f32, Precision::f64}) {
    const EvalRequest request{grid(11, 11), precision, false};
    const std::vector<std::uint8_t> mask = plate_mask(loops, request);
    ASSERT_EQ(mask.size(), 121u);
    std::size_t checked = 0;
    for (int a = 0; a <= 10; ++a)
      for (int b = 0; b <= 10; ++b) {
        const double u = a / 10.0, v = b / 10.0, d = signed_distance(u, v);
        if (std::abs(d) < 1e-12) continue;  // on an edge
        ++checked;
        EXPECT_EQ(mask[a * 11 + b], d < 0 ? 1 : 0) << u << "," << v;
      }
    EXPECT_GT(checked, 80u);
  }
}

// Signed distance to a convex polygon given counter-clockwise: the largest distance beyond any of
// its edges' lines, negative inside, zero on an edge.
double convex_signed_distance(const std::vector<Point2>& corners, double u, double v) {
  double d = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const Point2 a = corners[k], b = corners[(k + 1) % corners.size()];
    const double eu = b[0] - a[0], ev = b[1] - a[1];
    d = std::max(d, -(eu * (v - a[1]) - ev * (u - a[0])) / std::hypot(eu, ev));
  }
  return d;
}

TEST(CpuTensorTrim, VerticesOnTheRowsCountOnce) {
  // A kite with vertices on the rows u = 0.1, 0.5, 0.9 and the columns v = 0.1, 0.5, 0.7.
  const std::vector<Point2> kite = {{0.5, 0.1}, {0.9, 0.5}, {0.5, 0.7}, {0.1, 0.5}};
  expect_mask({polygon(kite)},
              [&](double u, double v) { return convex_signed_distance(kite, u, v); });
}

TEST(CpuTensorTrim, EdgesAlongRowsAndColumns) {
  // [0.2, 0.8] x [0.1, 0.9] minus [0.4, 0.6] x [0.3, 0.5], one loop each way round: their sides
  // lie on the rows u = 0.2, 0.4, 0.6, 0.8 and on the columns v = 0.1, 0.3, 0.5, 0.9.
  const auto box = [](double u, double v, double u0, double u1, double v0, double v1) {
    return std::max({u0 - u, u - u1, v0 - v, v - v1});
  };
  expect_mask({polygon({{0.2, 0.1}, {0.8, 0.1}, {0.8, 0.9}, {0.2, 0.9}}),
               polygon({{0.4, 0.3}, {0.4, 0.5}, {0.6, 0.5}, {0.6, 0.3}})},
              [&](double u, double v) {
                return std::max(box(u, v, 0.2, 0.8, 0.1, 0.9), -box(u, v, 0.4, 0.6, 0.3, 0.5));
              });
}

// The row fill by runs is the reference's per-sample rule (inside_by_events: an odd number of
// events strictly beyond the sample), including samples exactly on an event, repeated samples (a
// span grid's shared knots), repeated events (a tangency) and events beyond either end.
TEST(CpuTensorTrim, RowFillIsThePerSampleRule) {
  const std::vector<double> along = {0.0, 0.1, 0.1, 0.25, 0.5, 0.5, 0.75, 0.9, 1.0};
  const std::vector<std::vector<double>> event_lists = {
      {},         {0.3, 0.6}, {0.1, 0.75},  {0.1, 0.1, 0.5, 0.9}, {-1.0, 0.2, 0.2, 0.5, 2.0},
      {0.0, 1.0}, {0.5},      {-2.0, -1.0}, {0.05, 0.95, 1.5}};
  std::size_t inside_total = 0;
  for (const std::vector<double>& events : event_lists) {
    std::vector<std::uint8_t> inside(along.size(), 7);
    tensor::fill_row_from_events(events, along.data(), along.size(), inside.data());
    for (std::size_t b = 0; b < along.size(); ++b) {
      EXPECT_EQ(inside[b], inside_by_events(events, along[b]) ? 1 : 0)
          << "sample " << along[b] << " of " << ::testing::PrintToString(events);
      inside_total += inside[b];
    }
  }
  EXPECT_GT(inside_total, 10u);
}

// The gate (issue 15, part 3): the harness scores cpu-tensor's mask against the reference's exact
// classification (long double) and counts the samples outside the band classified differently.
TEST(CpuTensorTrim, NoSampleOutsideTheBandIsMisclassified) {
  ReferenceCache references;
  for (const char* scene_name : {"trimmed-plate", "hammer"}) {
    const Scene scene = *make_builtin_scene(scene_name);
    // Odd sizes, so the rows are not the reference's favourite round numbers.
    for (const Sampling& sampling : {grid(257, 263), span_grid(9)})
      for (Precision precision : {Precision::f32, Precision::f64}) {
        const std::string what =
            fmt::format("{} {} {}", scene_name, sampling.label(), to_string(precision));
        const Record r = measure(*find_strategy("cpu-tensor"), {}, scene,
                                 EvalRequest{sampling, precision, false}, 1, references);
        ASSERT_EQ(r.status, Status::ok) << what << ": " << r.reason;
        EXPECT_EQ(r.trimming, "classified") << what;
        ASSERT_TRUE(r.accuracy && r.accuracy->trim) << what;
        const TrimAccuracy& t = *r.accuracy->trim;
        ASSERT_TRUE(t.misclassified) << what;
        EXPECT_EQ(*t.misclassified, 0u) << what;
        // The mask is not one answer everywhere: the faces keep part of their samples.
        EXPECT_GT(t.inside, 0u) << what;
        EXPECT_LT(t.inside + t.boundary, r.points) << what;
      }
  }
}

}  // namespace
}  // namespace nurbs
