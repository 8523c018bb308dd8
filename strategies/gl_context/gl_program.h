// GLSL programs and the GL objects the GL strategies create, owned RAII-style. A shader that does
// not compile or link throws ShaderError carrying the driver's log (docs/design.md §GPU plumbing is
// shared: "A shader that fails to compile produces an error carrying the compiler log").
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "strategies/gl_context/gl_context.h"

namespace nurbs::gl {

class ShaderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Program {
 public:
  // `defines` ("#define PACKED 1\n") go right after the source's #version line. `label` names
  // the program in errors ("gl-pingpong basis_order.frag").
  Program(Context& context, std::string_view vertex, std::string_view fragment,
          std::string_view defines, std::string_view label);
  ~Program();
  Program(const Program&) = delete;
  Program& operator=(const Program&) = delete;

  GLuint id() const { return id_; }
  // Throws ShaderError when the program has no active uniform of that name.
  GLint uniform(const char* name) const;

 private:
  Context& context_;
  GLuint id_ = 0;
  std::string label_;
};

// A 2D texture (nearest filtering, clamped; read with texelFetch) with, for render targets, its
// own framebuffer.
class Texture {
 public:
  Texture() = default;
  Texture(Context& context, GLenum internal_format, int width, int height, bool render_target);
  ~Texture();
  Texture(Texture&& other) noexcept;
  Texture& operator=(Texture&& other) noexcept;

  // Replaces the whole image; returns the bytes sent.
  std::size_t upload(GLenum format, GLenum type, const void* data,
                     std::size_t bytes_per_texel) const;
  // Binds its framebuffer and sets the viewport to the whole texture.
  void bind_target() const;
  void bind_to_unit(int unit) const;

  GLuint id() const { return texture_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  void reset();
  Context* context_ = nullptr;
  GLuint texture_ = 0, framebuffer_ = 0;
  int width_ = 0, height_ = 0;
};

// Textures of one size and format written by one draw (multiple render targets): fragment
// output location i lands in texture(i). For passes that produce several sums at once, e.g. a
// point and its two partial derivatives.
class RenderTargets {
 public:
  RenderTargets() = default;
  RenderTargets(Context& context, GLenum internal_format, int width, int height, int count);
  ~RenderTargets();
  RenderTargets(RenderTargets&& other) noexcept;
  RenderTargets& operator=(RenderTargets&& other) noexcept;

  // Binds the framebuffer with every texture as a draw buffer and sets the viewport.
  void bind_target() const;
  const Texture& texture(int i) const { return textures_[static_cast<std::size_t>(i)]; }
  int count() const { return static_cast<int>(textures_.size()); }
  // Texture i, RGBA float, rows bottom to top: width * height * 4 floats.
  std::vector<float> read_rgba(int i) const;

 private:
  void reset();
  Context* context_ = nullptr;
  GLuint framebuffer_ = 0;
  std::vector<Texture> textures_;
};

// A buffer object pixel transfers go through: GL_PIXEL_PACK_BUFFER for read-backs (glReadPixels
// writes it on the device, one mapping copies it to the host), GL_PIXEL_UNPACK_BUFFER for uploads.
// Allocated at the first reserve() and grown, never re-allocated for a request it already holds:
// a repeated transfer pays for its bytes, not for an allocation and the first touch of its pages.
class PixelBuffer {
 public:
  // [0, bytes) of the buffer mapped; unmapped by release() (which throws when the driver lost the
  // content) or, without a check, when it goes.
  class Mapping {
   public:
    Mapping(Context& context, GLuint buffer, void* data, std::string_view where);
    ~Mapping();
    Mapping(Mapping&& other) noexcept;
    Mapping& operator=(Mapping&&) = delete;
    void* data() const { return data_; }
    void release();

   private:
    Context* context_;
    GLuint buffer_;
    void* data_;
    std::string where_;
  };

  PixelBuffer() = default;
  // `usage`: GL_STREAM_READ for a pack buffer, GL_STREAM_DRAW for an unpack buffer.
  PixelBuffer(Context& context, GLenum usage);
  ~PixelBuffer();
  PixelBuffer(PixelBuffer&& other) noexcept;
  PixelBuffer& operator=(PixelBuffer&& other) noexcept;

  // Makes the buffer hold at least `bytes`; a larger request re-allocates (the content is lost).
  void reserve(std::size_t bytes);
  std::size_t capacity() const { return capacity_; }
  GLuint id() const { return buffer_; }

  // glReadPixels of (x, y, width, height) of the bound read framebuffer's read buffer, as
  // `format` floats, into bytes from `offset`, rows `row_length` pixels apart (0: `width`): a
  // device copy (Context::copy_pixels_to_buffer). Reading GL_RGB from an RGBA32F target has the
  // driver drop w on the way: the host gets x y z runs without a pass of its own.
  void read_pixels(std::size_t offset, GLint x, GLint y, GLsizei width, GLsizei height,
                   GLenum format, GLint row_length = 0) const;
  // [0, bytes) mapped for reading (a host read-back: waits for the copies into it) or for writing
  // (the previous content discarded).
  Mapping map_read(std::size_t bytes, std::string_view where) const;
  Mapping map_write(std::size_t bytes, std::string_view where) const;

 private:
  void reset();
  Context* context_ = nullptr;
  GLenum usage_ = GL_STREAM_READ;
  GLuint buffer_ = 0;
  std::size_t capacity_ = 0;
};

// The empty vertex array a core profile needs to draw fullscreen_triangle.vert: one draw() is
// one fragment-program pass over the bound target's viewport.
class FullscreenTriangle {
 public:
  explicit FullscreenTriangle(Context& context);
  ~FullscreenTriangle();
  FullscreenTriangle(const FullscreenTriangle&) = delete;
  FullscreenTriangle& operator=(const FullscreenTriangle&) = delete;

  void draw() const;

 private:
  Context& context_;
  GLuint vertex_array_ = 0;
};

}  // namespace nurbs::gl
