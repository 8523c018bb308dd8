// vk-ksquad render(): crack-free in grid mode (patches share their boundary samples on every knot
// line), checked against the reference's projected silhouette; world-up at the top of the image.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iostream>
#include <vector>

#include "reference/nurbs_math.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "strategies/vk_ksquad/ksquad_settings.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"

namespace nurbs {
namespace {

using Pixel = std::array<double, 2>;

// Framebuffer position of a world point under the column-major matrix `m`: Vulkan's viewport
// transform, x right and y = (ndc y + 1) / 2 * height counted from the top row.
Pixel to_pixel(const std::array<float, 16>& m, const Vec3<double>& p, int width, int height) {
  double clip[4];
  for (int r = 0; r < 4; ++r) clip[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
  return {(clip[0] / clip[3] + 1) * 0.5 * width, (clip[1] / clip[3] + 1) * 0.5 * height};
}

double segment_distance(const Pixel& q, const Pixel& a, const Pixel& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1];
  const double len2 = dx * dx + dy * dy;
  double t = len2 > 0 ? ((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / len2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(q[0] - a[0] - t * dx, q[1] - a[1] - t * dy);
}

// Even-odd test of q against the closed polygon, and its distance to the polygon's edges.
std::pair<bool, double> inside_and_distance(const Pixel& q, const std::vector<Pixel>& polygon) {
  bool inside = false;
  double nearest = 1e300;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Pixel &a = polygon[i], &b = polygon[j];
    if ((a[1] > q[1]) != (b[1] > q[1]) &&
        q[0] < (b[0] - a[0]) * (q[1] - a[1]) / (b[1] - a[1]) + a[0])
      inside = !inside;
    nearest = std::min(nearest, segment_distance(q, a, b));
  }
  return {inside, nearest};
}

// patch144 seen from above (it is a height field over [0, 10]^2, so it faces the camera), off
// centre so a mirrored image would not match. The reference's silhouette: the boundary of the
// domain evaluated in double (400 points per side) and projected with the strategy's camera.
// Every pixel whose centre is inside it by more than `margin` pixels must be covered (a gap
// along a knot line shows the cleared background), and every pixel outside by more than the
// margin must be background. The margin absorbs the chords of the tessellated boundary and the
// rasterization rules; grid(8, 8) leaves the knot span [0.5, 0.55] of u without samples.
TEST(vk_ksquad_render, GridRenderHasNoGapsInsideTheReferenceSilhouette) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  const Scene scene = *make_builtin_scene("patch144");
  StrategyOptions options;
  options.extra = {{"vk-eye", "3,6,25"}, {"vk-center", "3,6,0"}, {"vk-viewport", "256x192"}};
  const vk_ksquad::KsquadSettings settings = vk_ksquad::ksquad_settings(options);
  const std::array<float, 16> camera = vk_ksquad::scene_camera(scene, settings);
  const int width = 256, height = 192;
  const Surface& s = scene.surfaces[0];
  const SurfaceNet<double> net(s);
  std::vector<Pixel> silhouette;
  const int n = 400;
  const auto add = [&](double u, double v) {
    silhouette.push_back(to_pixel(camera, surface_point(net, u, v), width, height));
  };
  const double u0 = s.u_min(), u1 = s.u_max(), v0 = s.v_min(), v1 = s.v_max();
  for (int k = 0; k < n; ++k) add(u0 + (u1 - u0) * k / n, v0);
  for (int k = 0; k < n; ++k) add(u1, v0 + (v1 - v0) * k / n);
  for (int k = 0; k < n; ++k) add(u1 - (u1 - u0) * k / n, v1);
  for (int k = 0; k < n; ++k) add(u0, v1 - (v1 - v0) * k / n);

  // World-up: looking down -z the camera's up is +y; with the projection's y flip it is at the
  // top of the image (a smaller row).
  EXPECT_LT(to_pixel(camera, {3, 7, 0}, width, height)[1],
            to_pixel(camera, {3, 6, 0}, width, height)[1]);

  const double margin = 2.0;
  for (const auto& [nu, nv] : {std::pair{8, 8}, std::pair{33, 29}}) {
    SCOPED_TRACE(testing::Message() << "grid " << nu << "x" << nv);
    auto strategy = make_vk_ksquad(options);
    Sampling sampling;
    sampling.grid_u = nu;
    sampling.grid_v = nv;
    strategy->prepare(scene, EvalRequest{sampling, Precision::f32, false});
    ASSERT_TRUE(strategy->render());
    const std::optional<RenderedImage> image = strategy->last_render();
    ASSERT_TRUE(image);
    ASSERT_EQ(image->width, width);
    ASSERT_EQ(image->height, height);
    std::size_t inside = 0, holes = 0, outside = 0, stray = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const auto [in, distance] = inside_and_distance({x + 0.5, y + 0.5}, silhouette);
        if (distance <= margin) continue;
        const bool covered = image->rgba[4 * (static_cast<std::size_t>(y) * width + x) + 3] != 0;
        if (in) {
          ++inside;
          holes += !covered;
        } else {
          ++outside;
          stray += covered;
        }
      }
    EXPECT_GT(inside, static_cast<std::size_t>(width * height / 10)) << "the patch is in view";
    EXPECT_GT(outside, 0u);
    EXPECT_EQ(holes, 0u) << "background pixels inside the silhouette";
    EXPECT_EQ(stray, 0u) << "covered pixels outside the silhouette";
    std::cout << "patch144 grid " << nu << "x" << nv << " render: " << inside
              << " pixels inside the silhouette, " << holes << " holes\n";
  }
}

}  // namespace
}  // namespace nurbs
