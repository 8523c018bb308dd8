#include "strategies/glsl_deboor/renderer.h"

#include <fmt/format.h>

namespace nurbs::embedded {
extern const std::string_view glsl_deboor_render_vert;
extern const std::string_view glsl_deboor_render_frag;
}  // namespace nurbs::embedded

namespace nurbs::glsl_deboor {

Renderer::Renderer(gl::Context& context, int width, int height)
    : context_(context),
      width_(width),
      height_(height),
      fetch_(context, embedded::glsl_deboor_render_vert, embedded::glsl_deboor_render_frag,
             "#define VERTEX_FETCH 1\n", "glsl-deboor render.vert (vertex texture fetch)"),
      traditional_(context, embedded::glsl_deboor_render_vert, embedded::glsl_deboor_render_frag,
                   "#define VERTEX_FETCH 0\n", "glsl-deboor render.vert (vertex buffer)") {
  const gl::Functions& gl = context_.gl();
  gl.GenTextures(1, &color_);
  gl.BindTexture(GL_TEXTURE_2D, color_);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  gl.GenRenderbuffers(1, &depth_);
  gl.BindRenderbuffer(GL_RENDERBUFFER, depth_);
  gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  gl.GenFramebuffers(1, &framebuffer_);
  gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_, 0);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw gl::Error(fmt::format("glsl-deboor render target incomplete (0x{:04x})", status));
  gl.GenVertexArrays(1, &vertex_array_);
  gl.GenBuffers(1, &vertex_buffer_);
  gl.UseProgram(fetch_.id());
  gl.Uniform1i(fetch_.uniform("points"), 0);
  gl.UseProgram(0);
  context_.check("glsl-deboor renderer");
}

Renderer::~Renderer() {
  context_.make_current();
  const gl::Functions& gl = context_.gl();
  for (auto& [size, buffer] : index_buffers_) gl.DeleteBuffers(1, &buffer.first);
  gl.DeleteBuffers(1, &vertex_buffer_);
  gl.DeleteVertexArrays(1, &vertex_array_);
  gl.DeleteFramebuffers(1, &framebuffer_);
  gl.DeleteRenderbuffers(1, &depth_);
  gl.DeleteTextures(1, &color_);
}

GLuint Renderer::index_buffer(int nu, int nv) {
  auto [it, added] = index_buffers_.try_emplace({nu, nv});
  if (added) {
    // Two triangles per grid cell; vertex k = b * nu + a.
    std::vector<GLuint> indices;
    indices.reserve(static_cast<std::size_t>(nu - 1) * (nv - 1) * 6);
    for (int b = 0; b + 1 < nv; ++b)
      for (int a = 0; a + 1 < nu; ++a) {
        const GLuint k = static_cast<GLuint>(b * nu + a), up = k + static_cast<GLuint>(nu);
        for (GLuint i : {k, k + 1, up + 1, k, up + 1, up}) indices.push_back(i);
      }
    const gl::Functions& gl = context_.gl();
    gl.GenBuffers(1, &it->second.first);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, it->second.first);
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(GLuint)),
                  indices.data(), GL_STATIC_DRAW);
    it->second.second = static_cast<GLsizei>(indices.size());
  }
  return it->second.first;
}

void Renderer::begin_frame() {
  const gl::Functions& gl = context_.gl();
  gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  gl.Viewport(0, 0, width_, height_);
  gl.ClearColor(0, 0, 0, 0);
  gl.Enable(GL_DEPTH_TEST);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.BindVertexArray(vertex_array_);
}

void Renderer::draw_without_read_back(const Evaluator& evaluator, const float mvp[16]) {
  const gl::Functions& gl = context_.gl();
  begin_frame();
  gl.UseProgram(fetch_.id());
  gl.UniformMatrix4fv(fetch_.uniform("mvp"), 1, GL_FALSE, mvp);
  const GLint nu = fetch_.uniform("nu"), row0 = fetch_.uniform("output_row0");
  for (const Page& page : evaluator.pages()) {
    page.points.bind_to_unit(0);
    for (const SurfaceSlot& s : page.slots) {
      gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer(s.nu, s.nv));
      gl.Uniform1i(nu, s.nu);
      gl.Uniform1i(row0, s.output_row0);
      gl.DrawElements(GL_TRIANGLES, index_buffers_.at({s.nu, s.nv}).second, GL_UNSIGNED_INT,
                      nullptr);
    }
  }
  gl.Disable(GL_DEPTH_TEST);
  context_.check("glsl-deboor render (vertex texture fetch)");
}

void Renderer::draw_with_read_back(Evaluator& evaluator, const float mvp[16]) {
  const std::vector<std::vector<float>> xyz = evaluator.read_back();
  const gl::Functions& gl = context_.gl();
  begin_frame();
  gl.UseProgram(traditional_.id());
  gl.UniformMatrix4fv(traditional_.uniform("mvp"), 1, GL_FALSE, mvp);
  gl.BindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  gl.EnableVertexAttribArray(0);
  std::vector<float> vertices;
  for (const Page& page : evaluator.pages())
    for (const SurfaceSlot& s : page.slots) {
      // read_back orders samples a * nv + b; the index buffer wants b * nu + a.
      const std::vector<float>& p = xyz[s.surface];
      vertices.resize(p.size());
      for (int a = 0; a < s.nu; ++a)
        for (int b = 0; b < s.nv; ++b)
          for (int c = 0; c < 3; ++c)
            vertices[(static_cast<std::size_t>(b) * s.nu + a) * 3 + c] =
                p[(static_cast<std::size_t>(a) * s.nv + b) * 3 + c];
      gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
                    vertices.data(), GL_STREAM_DRAW);
      gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
      gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer(s.nu, s.nv));
      gl.DrawElements(GL_TRIANGLES, index_buffers_.at({s.nu, s.nv}).second, GL_UNSIGNED_INT,
                      nullptr);
    }
  gl.Disable(GL_DEPTH_TEST);
  context_.check("glsl-deboor render (read back, vertex buffer)");
}

std::vector<unsigned char> Renderer::image() {
  const gl::Functions& gl = context_.gl();
  std::vector<unsigned char> pixels(static_cast<std::size_t>(width_) * height_ * 4);
  gl.BindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  context_.check("glsl-deboor render image");
  return pixels;
}

}  // namespace nurbs::glsl_deboor
