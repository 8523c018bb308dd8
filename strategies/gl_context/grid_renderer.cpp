#include "strategies/gl_context/grid_renderer.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace nurbs::embedded {
extern const std::string_view gl_grid_render_vert;
extern const std::string_view gl_grid_render_frag;
}  // namespace nurbs::embedded

namespace nurbs::gl {
namespace {

// Texture units of the render programs.
constexpr int kPointsUnit = 0, kTrimUnit = 1, kParametersUnit = 2;

}  // namespace

std::vector<GLuint> grid_triangle_indices(int nu, int nv) {
  std::vector<GLuint> indices;
  if (nu < 2 || nv < 2) return indices;
  indices.reserve(static_cast<std::size_t>(nu - 1) * (nv - 1) * 6);
  for (int b = 0; b + 1 < nv; ++b)
    for (int a = 0; a + 1 < nu; ++a) {
      const GLuint k = static_cast<GLuint>(b * nu + a), up = k + static_cast<GLuint>(nu);
      for (GLuint i : {k, k + 1, up + 1, k, up + 1, up}) indices.push_back(i);
    }
  return indices;
}

std::array<float, 16> orthographic_view(const Scene& scene) {
  Point3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Surface& s : scene.surfaces)
    for (const Point3& p : s.points)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], p[c]);
        hi[c] = std::max(hi[c], p[c]);
      }
  const double extent = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-30});
  const double scale = 1.8 / extent;
  std::array<float, 16> m{};
  m[0] = static_cast<float>(scale);
  m[5] = static_cast<float>(scale);
  m[10] = static_cast<float>(-scale);
  m[12] = static_cast<float>(-scale * 0.5 * (lo[0] + hi[0]));
  m[13] = static_cast<float>(-scale * 0.5 * (lo[1] + hi[1]));
  m[14] = static_cast<float>(scale * 0.5 * (lo[2] + hi[2]));
  m[15] = 1;
  return m;
}

GridRenderer::Variant GridRenderer::variant(bool fetch) {
  auto program = std::make_unique<Program>(
      context_, embedded::gl_grid_render_vert, embedded::gl_grid_render_frag,
      fetch ? "#define VERTEX_FETCH 1\n" : "#define VERTEX_FETCH 0\n",
      fetch ? "grid_render.vert (vertex texture fetch)" : "grid_render.vert (vertex buffer)");
  const GLint mvp = program->uniform("mvp"), nu = program->uniform("nu"),
              v_major = program->uniform("v_major"), trimmed = program->uniform("trimmed"),
              first = program->uniform("first_sample");
  const Functions& gl = context_.gl();
  gl.UseProgram(program->id());
  if (fetch) gl.Uniform1i(program->uniform("points"), kPointsUnit);
  gl.Uniform1i(program->uniform("trim"), kTrimUnit);
  gl.Uniform1i(program->uniform("parameters"), kParametersUnit);
  gl.UseProgram(0);
  return {std::move(program), mvp, nu, v_major, trimmed, first};
}

GridRenderer::GridRenderer(Context& context, int width, int height)
    : context_(context),
      width_(width),
      height_(height),
      fetch_(variant(true)),
      traditional_(variant(false)),
      origin_(fetch_.program->uniform("origin")),
      u_along_x_(fetch_.program->uniform("u_along_x")) {
  const Functions& gl = context_.gl();
  gl.GenTextures(1, &color_);
  gl.BindTexture(GL_TEXTURE_2D, color_);
  gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  gl.GenRenderbuffers(1, &depth_);
  gl.BindRenderbuffer(GL_RENDERBUFFER, depth_);
  gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
  gl.GenFramebuffers(1, &framebuffer_);
  context_.bind_framebuffer(framebuffer_);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_, 0);
  gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw Error(fmt::format("grid render target incomplete (0x{:04x})", status));
  gl.GenVertexArrays(1, &vertex_array_);
  gl.GenBuffers(1, &vertex_buffer_);
  context_.check("grid renderer");
}

GridRenderer::~GridRenderer() {
  context_.make_current();
  const Functions& gl = context_.gl();
  for (auto& [size, buffer] : index_buffers_) gl.DeleteBuffers(1, &buffer.first);
  gl.DeleteBuffers(1, &vertex_buffer_);
  gl.DeleteVertexArrays(1, &vertex_array_);
  gl.DeleteFramebuffers(1, &framebuffer_);
  gl.DeleteRenderbuffers(1, &depth_);
  gl.DeleteTextures(1, &color_);
}

GLsizei GridRenderer::rebuild_index_buffer(int nu, int nv) {
  const Functions& gl = context_.gl();
  // The element buffer binding is vertex-array state: keep it on this renderer's.
  gl.BindVertexArray(vertex_array_);
  auto& [buffer, count] = index_buffers_[{nu, nv}];
  if (!buffer) gl.GenBuffers(1, &buffer);
  const std::vector<GLuint> indices = grid_triangle_indices(nu, nv);
  gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffer);
  gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(indices.size() * sizeof(GLuint)),
                indices.data(), GL_STATIC_DRAW);
  GLint bytes = 0;
  gl.GetBufferParameteriv(GL_ELEMENT_ARRAY_BUFFER, GL_BUFFER_SIZE, &bytes);
  count = static_cast<GLsizei>(static_cast<std::size_t>(bytes) / sizeof(GLuint));
  return count;
}

GLsizei GridRenderer::index_buffer(int nu, int nv) {
  const auto it = index_buffers_.find({nu, nv});
  if (it == index_buffers_.end()) return rebuild_index_buffer(nu, nv);
  context_.gl().BindBuffer(GL_ELEMENT_ARRAY_BUFFER, it->second.first);
  return it->second.second;
}

void GridRenderer::begin_frame() {
  const Functions& gl = context_.gl();
  context_.bind_framebuffer(framebuffer_);
  gl.Viewport(0, 0, width_, height_);
  gl.ClearColor(0, 0, 0, 0);
  gl.Enable(GL_DEPTH_TEST);
  gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.BindVertexArray(vertex_array_);
}

void GridRenderer::set_common(const Variant& v, const float mvp[16], int nu, const GridTrim* trim,
                              bool v_major) {
  const Functions& gl = context_.gl();
  gl.UseProgram(v.program->id());
  gl.UniformMatrix4fv(v.mvp, 1, GL_FALSE, mvp);
  gl.Uniform1i(v.nu, nu);
  gl.Uniform1i(v.v_major, v_major ? 1 : 0);
  gl.Uniform1i(v.trimmed, trim ? 1 : 0);
  if (trim) {
    trim->trim->bind_to_unit(kTrimUnit);
    trim->parameters->bind_to_unit(kParametersUnit);
    gl.Uniform2i(v.first_sample, trim->first_u, trim->first_v);
  }
}

void GridRenderer::draw(const GridPoints& grid, const float mvp[16], const GridTrim* trim) {
  if (grid.nu < 2 || grid.nv < 2) return;
  const Functions& gl = context_.gl();
  set_common(fetch_, mvp, grid.nu, trim);
  grid.texture->bind_to_unit(kPointsUnit);
  gl.Uniform2i(origin_, grid.origin_x, grid.origin_y);
  gl.Uniform1i(u_along_x_, grid.u_along_x ? 1 : 0);
  context_.draw_elements(GL_TRIANGLES, index_buffer(grid.nu, grid.nv), GL_UNSIGNED_INT, nullptr);
}

void GridRenderer::upload_vertices(const float* xyz, int nu, int nv) {
  const Functions& gl = context_.gl();
  // The index buffer wants vertex k = b * nu + a.
  vertices_.resize(static_cast<std::size_t>(nu) * nv * 3);
  for (int a = 0; a < nu; ++a)
    for (int b = 0; b < nv; ++b)
      for (int c = 0; c < 3; ++c)
        vertices_[(static_cast<std::size_t>(b) * nu + a) * 3 + c] =
            xyz[(static_cast<std::size_t>(a) * nv + b) * 3 + c];
  // The attribute layout is vertex-array state: keep it on this renderer's.
  gl.BindVertexArray(vertex_array_);
  gl.BindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  gl.EnableVertexAttribArray(0);
  gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices_.size() * sizeof(float)),
                vertices_.data(), GL_STREAM_DRAW);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
}

void GridRenderer::draw(const float* xyz, int nu, int nv, const float mvp[16],
                        const GridTrim* trim) {
  if (nu < 2 || nv < 2) return;
  set_common(traditional_, mvp, nu, trim);
  upload_vertices(xyz, nu, nv);
  context_.draw_elements(GL_TRIANGLES, index_buffer(nu, nv), GL_UNSIGNED_INT, nullptr);
}

std::uint64_t GridRenderer::draw_device_points(GLuint vertex_buffer, int nu, int nv,
                                               const float mvp[16], const GridTrim* trim) {
  if (nu < 2 || nv < 2) return 0;
  const Functions& gl = context_.gl();
  // Vertex k = a * nv + b: the shader's v-major indexing, for the trim lookup.
  set_common(traditional_, mvp, nv, trim, true);
  gl.BindVertexArray(vertex_array_);
  gl.BindBuffer(GL_ARRAY_BUFFER, vertex_buffer);
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
  // Vertex k = a * nv + b: the index buffer of the transposed grid (its "a" runs along v) names
  // the same cells.
  const GLsizei elements = index_buffer(nv, nu);
  context_.draw_elements(GL_TRIANGLES, elements, GL_UNSIGNED_INT, nullptr);
  return static_cast<std::uint64_t>(elements) / 3;
}

void GridRenderer::end_frame(std::string_view where) {
  context_.gl().Disable(GL_DEPTH_TEST);
  context_.check(where);
}

std::vector<unsigned char> GridRenderer::image() {
  const Functions& gl = context_.gl();
  std::vector<unsigned char> pixels(static_cast<std::size_t>(width_) * height_ * 4);
  context_.bind_framebuffer(framebuffer_);
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  context_.read_pixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  context_.check("grid render image");
  return pixels;
}

RenderedImage GridRenderer::picture() {
  const std::vector<unsigned char> bottom_up = image();
  RenderedImage out{width_, height_, std::vector<std::uint8_t>(bottom_up.size())};
  const std::size_t row = static_cast<std::size_t>(width_) * 4;
  for (int y = 0; y < height_; ++y)
    std::copy_n(bottom_up.begin() + static_cast<std::ptrdiff_t>(row * (height_ - 1 - y)), row,
                out.rgba.begin() + static_cast<std::ptrdiff_t>(row * y));
  return out;
}

std::optional<RenderedImage> last_picture(Context& context, GridRenderer* renderer) {
  if (!renderer) return std::nullopt;
  context.make_current();
  return renderer->picture();
}

}  // namespace nurbs::gl
