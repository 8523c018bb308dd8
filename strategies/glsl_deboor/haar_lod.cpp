#include "strategies/glsl_deboor/haar_lod.h"

#include <fmt/format.h>

#include "strategies/strategy.h"

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
extern const std::string_view glsl_deboor_haar_forward_frag;
extern const std::string_view glsl_deboor_haar_inverse_frag;
}  // namespace nurbs::embedded

namespace nurbs::glsl_deboor {

HaarLod::HaarLod(gl::Context& context, const Page& page, const SurfaceSlot& slot, int levels)
    : context_(context),
      page_(page),
      slot_(slot),
      forward_(context, embedded::gl_fullscreen_triangle_vert,
               embedded::glsl_deboor_haar_forward_frag, "", "glsl-deboor haar_forward.frag"),
      inverse_(context, embedded::gl_fullscreen_triangle_vert,
               embedded::glsl_deboor_haar_inverse_frag, "", "glsl-deboor haar_inverse.frag") {
  int w = slot.nu, h = slot.nv;
  for (int k = 0; k <= levels; ++k) {
    if (k < levels && (w % 2 != 0 || h % 2 != 0))
      throw RefusedError(fmt::format("Haar level {} of a {}x{} grid: sizes must be even", k + 1,
                                     slot.nu, slot.nv));
    // Laid out as the de Boor output is (v along x, see Page): the row step halves v, the column
    // step u; the 2x2 averages are the same either way round.
    Level l;
    l.width = w;
    l.height = h;
    l.points = gl::Texture(context, GL_RGBA32F, h, w, true);
    if (k < levels) {
      l.half = gl::Texture(context, GL_RGBA32F, h / 2, w, true);
      l.d_rows = gl::Texture(context, GL_RGBA32F, h / 2, w, false);
      l.d_columns = gl::Texture(context, GL_RGBA32F, h / 2, w / 2, false);
    }
    levels_.push_back(std::move(l));
    w /= 2;
    h /= 2;
  }
  for (std::size_t k = 0; k + 1 < levels_.size(); ++k) {
    levels_[k].row_targets = two_targets(levels_[k].half, levels_[k].d_rows);
    levels_[k].column_targets = two_targets(levels_[k + 1].points, levels_[k].d_columns);
  }
  const gl::Functions& gl = context.gl();
  gl.GenVertexArrays(1, &vertex_array_);
  gl.UseProgram(inverse_.id());
  gl.Uniform1i(inverse_.uniform("average"), 0);
  gl.Uniform1i(inverse_.uniform("detail"), 1);
  gl.UseProgram(forward_.id());
  gl.Uniform1i(forward_.uniform("level"), 0);
  gl.UseProgram(0);
  context.check("glsl-deboor Haar levels");
}

HaarLod::~HaarLod() {
  context_.make_current();
  const gl::Functions& gl = context_.gl();
  for (Level& l : levels_) {
    if (l.row_targets) gl.DeleteFramebuffers(1, &l.row_targets);
    if (l.column_targets) gl.DeleteFramebuffers(1, &l.column_targets);
  }
  gl.DeleteVertexArrays(1, &vertex_array_);
}

GLuint HaarLod::two_targets(const gl::Texture& a, const gl::Texture& d) {
  const gl::Functions& gl = context_.gl();
  GLuint fb = 0;
  gl.GenFramebuffers(1, &fb);
  context_.bind_framebuffer(fb);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, a.id(), 0);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, d.id(), 0);
  const GLenum buffers[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  gl.DrawBuffers(2, buffers);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw gl::Error("glsl-deboor Haar: MRT framebuffer incomplete");
  return fb;
}

void HaarLod::forward(int k) {
  const gl::Functions& gl = context_.gl();
  Level& l = levels_[static_cast<std::size_t>(k)];
  gl.UseProgram(forward_.id());
  gl.BindVertexArray(vertex_array_);
  // Row step: level k -> (half, d_rows).
  context_.bind_framebuffer(l.row_targets);
  gl.Viewport(0, 0, l.height / 2, l.width);
  if (k == 0) {
    page_.points.bind_to_unit(0);
    gl.Uniform2i(forward_.uniform("origin"), 0, slot_.output_row0);
  } else {
    l.points.bind_to_unit(0);
    gl.Uniform2i(forward_.uniform("origin"), 0, 0);
  }
  gl.Uniform1i(forward_.uniform("direction"), 0);
  context_.draw_arrays(GL_TRIANGLES, 0, 3);
  // Column step: half -> (level k+1, d_columns).
  context_.bind_framebuffer(l.column_targets);
  gl.Viewport(0, 0, l.height / 2, l.width / 2);
  l.half.bind_to_unit(0);
  gl.Uniform2i(forward_.uniform("origin"), 0, 0);
  gl.Uniform1i(forward_.uniform("direction"), 1);
  context_.draw_arrays(GL_TRIANGLES, 0, 3);
}

void HaarLod::inverse(int k) {
  const gl::Functions& gl = context_.gl();
  Level& l = levels_[static_cast<std::size_t>(k)];
  gl.UseProgram(inverse_.id());
  gl.BindVertexArray(vertex_array_);
  l.half.bind_target();
  levels_[static_cast<std::size_t>(k) + 1].points.bind_to_unit(0);
  l.d_columns.bind_to_unit(1);
  gl.Uniform1i(inverse_.uniform("direction"), 1);
  context_.draw_arrays(GL_TRIANGLES, 0, 3);
  l.points.bind_target();
  l.half.bind_to_unit(0);
  l.d_rows.bind_to_unit(1);
  gl.Uniform1i(inverse_.uniform("direction"), 0);
  context_.draw_arrays(GL_TRIANGLES, 0, 3);
}

gl::GridPoints HaarLod::grid(int k) const {
  // Sample (a, b) of level 0 is output texel (b, output_row0 + a) (as forward(0) reads it); the
  // levels' own textures hold sample (a, b) at texel (b, a).
  if (k == 0) return {&page_.points, slot_.nu, slot_.nv, 0, slot_.output_row0, false};
  const Level& l = levels_[static_cast<std::size_t>(k)];
  return {&l.points, l.width, l.height, 0, 0, false};
}

std::vector<float> HaarLod::read(int k) const {
  const gl::Functions& gl = context_.gl();
  const Level& l = levels_[static_cast<std::size_t>(k)];
  // Rows of the texture are runs of b: read as x y z, they are the result's order.
  std::vector<float> xyz(static_cast<std::size_t>(l.width) * l.height * 3);
  l.points.bind_target();
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  context_.read_pixels(0, 0, l.height, l.width, GL_RGB, GL_FLOAT, xyz.data());
  return xyz;
}

}  // namespace nurbs::glsl_deboor
