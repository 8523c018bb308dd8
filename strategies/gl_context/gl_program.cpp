#include "strategies/gl_context/gl_program.h"

#include <fmt/format.h>

#include <utility>
#include <vector>

namespace nurbs::gl {
namespace {

std::string shader_log(const Functions& gl, GLuint shader) {
  GLint length = 0;
  gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  gl.GetShaderInfoLog(shader, length, nullptr, log.data());
  return log.c_str();
}

std::string program_log(const Functions& gl, GLuint program) {
  GLint length = 0;
  gl.GetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  gl.GetProgramInfoLog(program, length, nullptr, log.data());
  return log.c_str();
}

// Splits after the #version line so that defines land where GLSL allows them.
std::pair<std::string_view, std::string_view> split_version(std::string_view source) {
  if (source.rfind("#version", 0) != 0) return {{}, source};
  const std::size_t end = source.find('\n');
  if (end == std::string_view::npos) return {source, {}};
  return {source.substr(0, end + 1), source.substr(end + 1)};
}

GLuint compile(const Functions& gl, GLenum stage, std::string_view source, std::string_view defines,
               std::string_view label) {
  const auto [version, body] = split_version(source);
  const std::string line = "#line 2\n";
  const char* parts[] = {version.data(), defines.data(), line.c_str(), body.data()};
  const GLint lengths[] = {static_cast<GLint>(version.size()), static_cast<GLint>(defines.size()),
                           static_cast<GLint>(line.size()), static_cast<GLint>(body.size())};
  const GLuint shader = gl.CreateShader(stage);
  gl.ShaderSource(shader, 4, parts, lengths);
  gl.CompileShader(shader);
  GLint ok = GL_FALSE;
  gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = shader_log(gl, shader);
    gl.DeleteShader(shader);
    throw ShaderError(fmt::format("{}: {} shader does not compile: {}", label,
                                  stage == GL_VERTEX_SHADER ? "vertex" : "fragment", log));
  }
  return shader;
}

}  // namespace

Program::Program(Context& context, std::string_view vertex, std::string_view fragment,
                 std::string_view defines, std::string_view label)
    : context_(context), label_(label) {
  context_.make_current();
  const Functions& gl = context_.gl();
  const GLuint vs = compile(gl, GL_VERTEX_SHADER, vertex, defines, label);
  GLuint fs = 0;
  try {
    fs = compile(gl, GL_FRAGMENT_SHADER, fragment, defines, label);
  } catch (...) {
    gl.DeleteShader(vs);
    throw;
  }
  id_ = gl.CreateProgram();
  gl.AttachShader(id_, vs);
  gl.AttachShader(id_, fs);
  gl.LinkProgram(id_);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  GLint ok = GL_FALSE;
  gl.GetProgramiv(id_, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = program_log(gl, id_);
    gl.DeleteProgram(id_);
    throw ShaderError(fmt::format("{}: program does not link: {}", label, log));
  }
  context_.check(label_);
}

Program::~Program() {
  context_.make_current();
  context_.gl().DeleteProgram(id_);
}

GLint Program::uniform(const char* name) const {
  const GLint location = context_.gl().GetUniformLocation(id_, name);
  if (location < 0) throw ShaderError(fmt::format("{}: no active uniform '{}'", label_, name));
  return location;
}

Texture::Texture(Context& context, GLenum internal_format, int width, int height,
                 bool render_target)
    : context_(&context), width_(width), height_(height) {
  const Functions& gl = context.gl();
  gl.GenTextures(1, &texture_);
  gl.BindTexture(GL_TEXTURE_2D, texture_);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  // Integer formats need an integer pixel format even with no data (GL 3.3 §8.5).
  const GLenum format = internal_format == GL_R32I      ? GL_RED_INTEGER
                        : internal_format == GL_RG32I   ? GL_RG_INTEGER
                        : internal_format == GL_RGBA32I ? GL_RGBA_INTEGER
                                                        : GL_RGBA;
  const bool integer = format != GL_RGBA;
  const GLenum type = integer ? GL_INT : GL_FLOAT;
  gl.TexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal_format), width, height, 0, format,
                type, nullptr);
  if (render_target) {
    gl.GenFramebuffers(1, &framebuffer_);
    context.bind_framebuffer(framebuffer_);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture_, 0);
    const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
      throw Error(fmt::format("framebuffer of a {}x{} float texture incomplete (0x{:04x})", width,
                              height, status));
  }
  context.check(fmt::format("texture {}x{}", width, height));
}

Texture::~Texture() {
  reset();
}

Texture::Texture(Texture&& other) noexcept {
  *this = std::move(other);
}

Texture& Texture::operator=(Texture&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    texture_ = std::exchange(other.texture_, 0);
    framebuffer_ = std::exchange(other.framebuffer_, 0);
    width_ = other.width_;
    height_ = other.height_;
  }
  return *this;
}

void Texture::reset() {
  if (!context_) return;
  context_->make_current();
  if (framebuffer_) context_->gl().DeleteFramebuffers(1, &framebuffer_);
  if (texture_) context_->gl().DeleteTextures(1, &texture_);
  framebuffer_ = texture_ = 0;
  context_ = nullptr;
}

std::size_t Texture::upload(GLenum format, GLenum type, const void* data,
                            std::size_t bytes_per_texel) const {
  const Functions& gl = context_->gl();
  gl.BindTexture(GL_TEXTURE_2D, texture_);
  gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
  gl.TexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, format, type, data);
  return bytes_per_texel * static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
}

void Texture::bind_target() const {
  const Functions& gl = context_->gl();
  context_->bind_framebuffer(framebuffer_);
  gl.Viewport(0, 0, width_, height_);
}

void Texture::bind_to_unit(int unit) const {
  const Functions& gl = context_->gl();
  gl.ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + unit));
  gl.BindTexture(GL_TEXTURE_2D, texture_);
}

RenderTargets::RenderTargets(Context& context, GLenum internal_format, int width, int height,
                             int count)
    : context_(&context) {
  const Functions& gl = context.gl();
  for (int i = 0; i < count; ++i)
    textures_.emplace_back(context, internal_format, width, height, false);
  gl.GenFramebuffers(1, &framebuffer_);
  context.bind_framebuffer(framebuffer_);
  std::vector<GLenum> buffers;
  for (int i = 0; i < count; ++i) {
    const GLenum attachment = static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D,
                            textures_[static_cast<std::size_t>(i)].id(), 0);
    buffers.push_back(attachment);
  }
  gl.DrawBuffers(count, buffers.data());
  const GLenum status = gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw Error(fmt::format("framebuffer of {} {}x{} textures incomplete (0x{:04x})", count, width,
                            height, status));
  context.check(fmt::format("{} render targets {}x{}", count, width, height));
}

RenderTargets::~RenderTargets() {
  reset();
}

RenderTargets::RenderTargets(RenderTargets&& other) noexcept {
  *this = std::move(other);
}

RenderTargets& RenderTargets::operator=(RenderTargets&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    framebuffer_ = std::exchange(other.framebuffer_, 0);
    textures_ = std::move(other.textures_);
  }
  return *this;
}

void RenderTargets::reset() {
  if (!context_) return;
  context_->make_current();
  if (framebuffer_) context_->gl().DeleteFramebuffers(1, &framebuffer_);
  framebuffer_ = 0;
  textures_.clear();
  context_ = nullptr;
}

void RenderTargets::bind_target() const {
  context_->bind_framebuffer(framebuffer_);
  context_->gl().Viewport(0, 0, textures_.front().width(), textures_.front().height());
}

std::vector<float> RenderTargets::read_rgba(int i) const {
  const Functions& gl = context_->gl();
  const Texture& t = texture(i);
  std::vector<float> texels(static_cast<std::size_t>(t.width()) * t.height() * 4);
  context_->bind_framebuffer(framebuffer_);
  gl.ReadBuffer(static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + i));
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  context_->read_pixels(0, 0, t.width(), t.height(), GL_RGBA, GL_FLOAT, texels.data());
  return texels;
}

PixelBuffer::Mapping::Mapping(Context& context, GLuint buffer, void* data, std::string_view where)
    : context_(&context), buffer_(buffer), data_(data), where_(where) {}

PixelBuffer::Mapping::Mapping(Mapping&& other) noexcept
    : context_(other.context_),
      buffer_(other.buffer_),
      data_(std::exchange(other.data_, nullptr)),
      where_(std::move(other.where_)) {}

PixelBuffer::Mapping::~Mapping() {
  if (!data_) return;
  try {
    release();
  } catch (const std::exception&) {
    // Unwinding from another error, or a caller that did not ask: nothing to report to.
  }
}

void PixelBuffer::Mapping::release() {
  if (!data_) return;
  data_ = nullptr;
  context_->make_current();
  context_->unmap_buffer(buffer_, where_);
}

PixelBuffer::PixelBuffer(Context& context, GLenum usage) : context_(&context), usage_(usage) {
  context.gl().GenBuffers(1, &buffer_);
}

PixelBuffer::~PixelBuffer() {
  reset();
}

PixelBuffer::PixelBuffer(PixelBuffer&& other) noexcept {
  *this = std::move(other);
}

PixelBuffer& PixelBuffer::operator=(PixelBuffer&& other) noexcept {
  if (this != &other) {
    reset();
    context_ = std::exchange(other.context_, nullptr);
    usage_ = other.usage_;
    buffer_ = std::exchange(other.buffer_, 0);
    capacity_ = std::exchange(other.capacity_, 0);
  }
  return *this;
}

void PixelBuffer::reset() {
  if (!context_) return;
  context_->make_current();
  if (buffer_) context_->gl().DeleteBuffers(1, &buffer_);
  buffer_ = 0;
  capacity_ = 0;
  context_ = nullptr;
}

void PixelBuffer::reserve(std::size_t bytes) {
  if (bytes <= capacity_) return;
  const Functions& gl = context_->gl();
  const GLenum target = usage_ == GL_STREAM_READ ? GL_PIXEL_PACK_BUFFER : GL_PIXEL_UNPACK_BUFFER;
  gl.BindBuffer(target, buffer_);
  gl.BufferData(target, static_cast<GLsizeiptr>(bytes), nullptr, usage_);
  gl.BindBuffer(target, 0);
  context_->check(fmt::format("pixel buffer of {} bytes", bytes));
  capacity_ = bytes;
}

void PixelBuffer::read_pixels(std::size_t offset, GLint x, GLint y, GLsizei width, GLsizei height,
                              GLenum format, GLint row_length) const {
  const Functions& gl = context_->gl();
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  gl.PixelStorei(GL_PACK_ROW_LENGTH, row_length);
  context_->copy_pixels_to_buffer(buffer_, x, y, width, height, format, GL_FLOAT,
                                  static_cast<GLintptr>(offset));
  if (row_length != 0) gl.PixelStorei(GL_PACK_ROW_LENGTH, 0);
}

PixelBuffer::Mapping PixelBuffer::map_read(std::size_t bytes, std::string_view where) const {
  return Mapping(
      *context_, buffer_,
      context_->map_buffer(buffer_, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT, where), where);
}

PixelBuffer::Mapping PixelBuffer::map_write(std::size_t bytes, std::string_view where) const {
  return Mapping(*context_, buffer_,
                 context_->map_buffer(buffer_, static_cast<GLsizeiptr>(bytes),
                                      GL_MAP_WRITE_BIT | GL_MAP_INVALIDATE_BUFFER_BIT, where),
                 where);
}

FullscreenTriangle::FullscreenTriangle(Context& context) : context_(context) {
  context_.gl().GenVertexArrays(1, &vertex_array_);
}

FullscreenTriangle::~FullscreenTriangle() {
  context_.make_current();
  context_.gl().DeleteVertexArrays(1, &vertex_array_);
}

void FullscreenTriangle::draw() const {
  context_.gl().BindVertexArray(vertex_array_);
  context_.draw_arrays(GL_TRIANGLES, 0, 3);
}

}  // namespace nurbs::gl
