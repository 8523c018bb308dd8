// 002 §4.2 and §4.1 side by side for glsl-deboor's output atlas, on the shared grid renderer
// (strategies/gl_context/grid_renderer.h): every surface of every page drawn straight from the de
// Boor output texture, or read back and re-uploaded. With `trims`, trimmed surfaces' fragments
// outside the trim are discarded (000 §4).
#pragma once

#include <vector>

#include "strategies/gl_context/grid_renderer.h"
#include "strategies/glsl_deboor/deboor_evaluator.h"

namespace nurbs::trim_texture {
class TrimTextures;
}

namespace nurbs::glsl_deboor {

class Renderer {
 public:
  Renderer(gl::Context& context, int width, int height) : grid_(context, width, height) {}

  void draw_without_read_back(const Evaluator& evaluator, const float mvp[16],
                              const trim_texture::TrimTextures* trims = nullptr);
  void draw_with_read_back(Evaluator& evaluator, const float mvp[16],
                           const trim_texture::TrimTextures* trims = nullptr);
  // The image (RGBA8, rows bottom-up) for tests.
  std::vector<unsigned char> image() { return grid_.image(); }
  gl::GridRenderer& grid() { return grid_; }

 private:
  gl::GridRenderer grid_;
  EvalResult read_back_;  // the last draw_with_read_back's points, storage kept for the next
};

}  // namespace nurbs::glsl_deboor
