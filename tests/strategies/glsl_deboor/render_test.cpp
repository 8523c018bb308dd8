// 002 §4.2: the sphere drawn straight from the de Boor output texture (vertex texture fetch, no
// read-back) covers the disc the reference says (radius 2 at the origin, orthographic view: a
// disc of 51.2 pixels in a 128-pixel image) to within 1.5 pixels, and the traditional path (read
// back, vertex buffer, §4.1) draws the identical image. Times are the `render` and
// `render_via_read_back` phases of `nurbsbench run` (docs/design.md §Timing: speed lives in
// benchmarks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "reference/sampling.h"
#include "scenes/builtin_scenes.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/glsl_deboor/renderer.h"

namespace nurbs::glsl_deboor {
namespace {

constexpr float kScale = 0.4f;  // sphere radius 2 -> 0.8 in clip space
constexpr float kMvp[16] = {kScale, 0, 0, 0, 0, kScale, 0, 0, 0, 0, -kScale, 0, 0, 0, 0, 1};

TEST(GlslDeBoorRender, SphereSilhouetteWithoutReadBack) {
  if (!gl::Context::probe(gl::Platform::egl).available) GTEST_SKIP();
  auto context = gl::Context::create(gl::Platform::egl);
  const Scene scene = *make_builtin_scene("sphere");
  Sampling grid;
  grid.grid_u = 64;
  grid.grid_v = 64;
  Evaluator evaluator(*context, context->max_texture_size());
  evaluator.prepare(scene, sample_parameters(scene, grid));
  evaluator.evaluate();
  Renderer renderer(*context, 128, 128);
  renderer.draw_without_read_back(evaluator, kMvp);
  const std::vector<unsigned char> fetched = renderer.image();
  renderer.draw_with_read_back(evaluator, kMvp);
  const std::vector<unsigned char> traditional = renderer.image();

  const double radius = 0.8 * 64, centre = 64;
  int inside = 0, outside = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      const double d = std::hypot(x + 0.5 - centre, y + 0.5 - centre);
      const bool covered =
          fetched[(static_cast<std::size_t>(y) * 128 + x) * 4 + 3] == 255;  // alpha
      if (d < radius - 1.5) {
        ++inside;
        EXPECT_TRUE(covered) << "pixel " << x << "," << y << " inside the disc";
      } else if (d > radius + 1.5) {
        ++outside;
        EXPECT_FALSE(covered) << "pixel " << x << "," << y << " outside the disc";
      }
    }
  EXPECT_GT(inside, 7000);
  EXPECT_GT(outside, 7000);
  EXPECT_EQ(fetched, traditional);
}

}  // namespace
}  // namespace nurbs::glsl_deboor
