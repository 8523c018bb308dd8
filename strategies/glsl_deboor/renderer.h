// 002 §4.2 and §4.1 side by side: drawing the evaluated grid of every surface as triangles into
// an offscreen framebuffer (RGBA8 + depth), either straight from the de Boor output texture by
// vertex texture fetch (no read-back; the index buffer is static, built once per resolution), or
// the traditional way (read the points back, upload them as a vertex buffer, draw).
#pragma once

#include <map>
#include <utility>
#include <vector>

#include "strategies/glsl_deboor/deboor_evaluator.h"

namespace nurbs::glsl_deboor {

class Renderer {
 public:
  Renderer(gl::Context& context, int width, int height);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // §4.2: every surface of every page, positions fetched from the output texture.
  void draw_without_read_back(const Evaluator& evaluator, const float mvp[16]);
  // §4.1: read back (Evaluator::read_back), re-upload as vertex buffers, draw.
  void draw_with_read_back(Evaluator& evaluator, const float mvp[16]);
  // The image (RGBA8, rows bottom-up) for tests.
  std::vector<unsigned char> image();
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  void begin_frame();
  GLuint index_buffer(int nu, int nv);  // built once per resolution, then reused

  gl::Context& context_;
  int width_, height_;
  GLuint framebuffer_ = 0, color_ = 0, depth_ = 0, vertex_array_ = 0, vertex_buffer_ = 0;
  gl::Program fetch_, traditional_;
  std::map<std::pair<int, int>, std::pair<GLuint, GLsizei>> index_buffers_;
};

}  // namespace nurbs::glsl_deboor
