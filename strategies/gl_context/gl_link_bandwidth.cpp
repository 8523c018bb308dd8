// The GL row of the host<->device link (strategies/link_copy.h): pixel transfers between buffer
// objects and an RGBA32F texture attached to a framebuffer, the way the GL strategies move their
// bytes: an upload is glTexSubImage2D from a GL_PIXEL_UNPACK_BUFFER the host wrote through a
// mapping, a read-back is glReadPixels into a GL_PIXEL_PACK_BUFFER that the host then maps for
// reading. Texture, framebuffer and both buffers are kept for the run and grown for a larger
// request.
#include <fmt/format.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>

#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_context/gl_program.h"
#include "strategies/link_copy.h"
#include "strategies/wall_clock.h"

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
}  // namespace nurbs::embedded

namespace nurbs::gl {
namespace {

constexpr std::size_t kTexelBytes = 4 * sizeof(float);
// Words checked after each copy: enough to catch a copy that did not happen or landed elsewhere,
// few enough that writing and reading them costs nothing beside the copies.
constexpr std::size_t kCheckedWords = 4096;

// The value word `i` carries in pass `pass`: an integer below 2^24, so a float holds it exactly
// and no driver's float path (NaN quieting, denormal flushing) can change it on the way.
float pattern(std::uint32_t pass, std::size_t i) {
  return static_cast<float>((pass * 7919u + static_cast<std::uint32_t>(i) * 2654435761u) &
                            0xffffffu);
}

class LinkBench final : public LinkCopy::Bench {
 public:
  explicit LinkBench(Platform platform) {
    setup_s_ = wall_seconds([&] {
      try {
        context_ = Context::create(platform);
      } catch (const UnavailableError& e) {
        throw std::runtime_error(fmt::format("unavailable: {}", e.what()));
      }
      unpack_ = PixelBuffer(*context_, GL_STREAM_DRAW);
      pack_ = PixelBuffer(*context_, GL_STREAM_READ);
    });
  }

  ~LinkBench() override {
    context_->make_current();
    mapping_.reset();
    triangle_.reset();
    fill_program_.reset();
    fill_target_ = Texture();
    texture_ = Texture();
    unpack_ = PixelBuffer();
    pack_ = PixelBuffer();
  }

  LinkTiming time(std::size_t bytes, int repetitions) override {
    context_->make_current();
    LinkTiming out;
    out.setup_s = setup_s_ + wall_seconds([&] {
                    fit(bytes);
                    unpack_.reserve(bytes);
                    pack_.reserve(bytes);
                    write_words(bytes, ++pass_);
                    upload(bytes);
                    read_back(bytes);
                    check_words(bytes, pass_, "the untimed copies");
                  });
    setup_s_ = 0;
    out.device = context_->device_info();
    out.method = fmt::format(
        "upload: glTexSubImage2D of an RGBA32F {}-texel-wide texture from a GL_PIXEL_UNPACK_BUFFER "
        "the host wrote through a mapping beforehand; read-back: glReadPixels of the texture's "
        "framebuffer into a GL_PIXEL_PACK_BUFFER, then glMapBufferRange(GL_MAP_READ_BIT); texture "
        "and buffers kept for the run; wall clock around the commands and a fence wait (and the "
        "mapping)",
        texture_.width());
    for (int k = 0; k < repetitions; ++k) {
      // New words go up before every copy and the pack buffer's copies of them are overwritten
      // first, so they can only come back by the two copies: one that did not happen fails.
      write_words(bytes, ++pass_);
      out.upload_s.push_back(wall_seconds([&] { upload(bytes); }));
      clear_pack_words(bytes);
      out.read_back_s.push_back(wall_seconds([&] {
        read_back(bytes);
        mapping_.emplace(pack_.map_read(bytes, "GL link read-back map"));
      }));
      check_words(bytes, pass_, "a timed copy");
    }
    return out;
  }

  // One draw of a constant colour over an RGBA32F target as wide as the link's texture (rows as
  // needed; several draws where they pass GL_MAX_TEXTURE_SIZE), scaled to the request's pixels
  // from the whole rows drawn. The colour carries the pass number, read back after the last pass:
  // a pass that did not happen fails.
  std::optional<PassTiming> fragment_pass(std::size_t pixels, int repetitions) override {
    context_->make_current();
    const Functions& gl = context_->gl();
    const std::size_t side = static_cast<std::size_t>(context_->max_texture_size());
    const std::size_t width = std::min(side, pixels);
    const std::size_t rows = (pixels + width - 1) / width;
    const std::size_t page_rows = std::min(rows, side);
    if (!fill_target_.id() || fill_target_.width() != static_cast<int>(width) ||
        fill_target_.height() < static_cast<int>(page_rows)) {
      fill_target_ = Texture();
      fill_target_ = Texture(*context_, GL_RGBA32F, static_cast<int>(width),
                             static_cast<int>(page_rows), true);
    }
    if (!fill_program_) {
      fill_program_.emplace(*context_, embedded::gl_fullscreen_triangle_vert,
                            "#version 330 core\n"
                            "uniform float pass_value;\n"
                            "out vec4 color;\n"
                            "void main() { color = vec4(gl_FragCoord.xy, pass_value, 1.0); }\n",
                            "", "limit fragment pass");
      triangle_.emplace(*context_);
    }
    const GLint value = fill_program_->uniform("pass_value");
    const auto draw_all = [&](float pass) {
      fill_target_.bind_target();
      gl.UseProgram(fill_program_->id());
      gl.Uniform1fv(value, 1, &pass);
      for (std::size_t done = 0; done < rows; done += page_rows) {
        const std::size_t here = std::min(page_rows, rows - done);
        gl.Viewport(0, 0, static_cast<GLsizei>(width), static_cast<GLsizei>(here));
        triangle_->draw();
      }
    };
    const double share =
        static_cast<double>(pixels) / static_cast<double>(rows * width);  // of what was drawn
    DeviceTimer timer(*context_);
    float pass = 0;
    timer.time("limit fragment pass (untimed)", [&] { draw_all(++pass); });
    PassTiming out;
    out.device = context_->device_info();
    out.method = fmt::format(
        "a constant-colour fragment program (no reads) drawn over an RGBA32F target {} pixels "
        "wide, one fullscreen triangle per {} rows; wall clock around the draws and glFinish, "
        "GL_TIME_ELAPSED beside it",
        width, page_rows);
    for (int k = 0; k < repetitions; ++k) {
      double device_s = 0;
      const double wall_s = wall_seconds(
          [&] { device_s = timer.time("limit fragment pass", [&] { draw_all(++pass); }); });
      out.seconds.push_back(wall_s * share);
      out.device_seconds.push_back(device_s * share);
    }
    float texel[4] = {0, 0, 0, 0};
    fill_target_.bind_target();
    gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    context_->read_pixels(0, 0, 1, 1, GL_RGBA, GL_FLOAT, texel);
    if (texel[2] != pass)
      throw std::runtime_error(fmt::format(
          "limit fragment pass ({}): pixel (0, 0) holds {} after pass {}: the draws did not "
          "happen",
          context_->description(), texel[2], pass));
    return out;
  }

 private:
  // The texture holds `bytes` as RGBA32F texels, GL_MAX_TEXTURE_SIZE wide at most, rows as needed;
  // kept when it already holds them.
  void fit(std::size_t bytes) {
    const std::size_t texels = bytes / kTexelBytes;
    const std::size_t side = static_cast<std::size_t>(context_->max_texture_size());
    if (texture_.id() &&
        rows_for(texels, texture_.width()) <= static_cast<std::size_t>(texture_.height()))
      return;
    const std::size_t width = std::min(side, texels);
    const std::size_t rows = rows_for(texels, static_cast<int>(width));
    if (rows > side)
      throw RefusedError(
          fmt::format("GL link: {} bytes need an RGBA32F texture of {} x {} texels, beyond "
                      "GL_MAX_TEXTURE_SIZE {} ({} bytes at most)",
                      bytes, width, rows, side, side * side * kTexelBytes));
    texture_ = Texture();
    texture_ =
        Texture(*context_, GL_RGBA32F, static_cast<int>(width), static_cast<int>(rows), true);
  }

  static std::size_t rows_for(std::size_t texels, int width) {
    const std::size_t w = static_cast<std::size_t>(width);
    return (texels + w - 1) / w;
  }

  // The texels as whole rows, then the part of a last row: two rectangles at most.
  template <typename F>
  void for_each_rectangle(std::size_t bytes, F&& f) const {
    const std::size_t texels = bytes / kTexelBytes;
    const std::size_t width = static_cast<std::size_t>(texture_.width());
    const std::size_t rows = texels / width, rest = texels % width;
    if (rows > 0) f(0, 0, static_cast<GLsizei>(width), static_cast<GLsizei>(rows), std::size_t{0});
    if (rest > 0)
      f(0, static_cast<GLint>(rows), static_cast<GLsizei>(rest), 1, rows * width * kTexelBytes);
  }

  void upload(std::size_t bytes) {
    const Functions& gl = context_->gl();
    gl.BindTexture(GL_TEXTURE_2D, texture_.id());
    gl.BindBuffer(GL_PIXEL_UNPACK_BUFFER, unpack_.id());
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for_each_rectangle(bytes, [&](GLint x, GLint y, GLsizei w, GLsizei h, std::size_t offset) {
      gl.TexSubImage2D(GL_TEXTURE_2D, 0, x, y, w, h, GL_RGBA, GL_FLOAT,
                       reinterpret_cast<const void*>(static_cast<std::uintptr_t>(offset)));
    });
    gl.BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    context_->finish("GL link upload");
    context_->check("GL link upload");
  }

  void read_back(std::size_t bytes) {
    mapping_.reset();
    texture_.bind_target();
    context_->gl().ReadBuffer(GL_COLOR_ATTACHMENT0);
    for_each_rectangle(bytes, [&](GLint x, GLint y, GLsizei w, GLsizei h, std::size_t offset) {
      pack_.read_pixels(offset, x, y, w, h, GL_RGBA);
    });
    context_->finish("GL link read-back");
    context_->check("GL link read-back");
  }

  static std::size_t word_stride(std::size_t words) {
    return std::max<std::size_t>(1, words / kCheckedWords);
  }

  // The checked words of the upload buffer, through a mapping that discards the rest (the copy
  // moves every byte whatever they hold).
  void write_words(std::size_t bytes, std::uint32_t pass) {
    mapping_.reset();
    PixelBuffer::Mapping m = unpack_.map_write(bytes, "GL link upload buffer");
    float* words = static_cast<float*>(m.data());
    const std::size_t n = bytes / sizeof(float), stride = word_stride(n);
    for (std::size_t i = 0; i < n; i += stride) words[i] = pattern(pass, i);
    words[n - 1] = pattern(pass, n - 1);
    m.release();
  }

  void clear_pack_words(std::size_t bytes) {
    mapping_.reset();
    PixelBuffer::Mapping m = pack_.map_write(bytes, "GL link read-back buffer");
    float* words = static_cast<float*>(m.data());
    const std::size_t n = bytes / sizeof(float), stride = word_stride(n);
    for (std::size_t i = 0; i < n; i += stride) words[i] = -1.0f;
    words[n - 1] = -1.0f;
    m.release();
  }

  void check_words(std::size_t bytes, std::uint32_t pass, std::string_view what) {
    if (!mapping_) mapping_.emplace(pack_.map_read(bytes, "GL link read-back map"));
    const float* words = static_cast<const float*>(mapping_->data());
    const std::size_t n = bytes / sizeof(float), stride = word_stride(n);
    auto check_one = [&](std::size_t i) {
      if (words[i] != pattern(pass, i))
        throw std::runtime_error(fmt::format(
            "GL link ({}): after {}, float {} of {} read back is {}, uploaded {}: a copy did not "
            "move the bytes",
            context_->description(), what, i, n, words[i], pattern(pass, i)));
    };
    for (std::size_t i = 0; i < n; i += stride) check_one(i);
    check_one(n - 1);
    mapping_->release();
    mapping_.reset();
  }

  std::unique_ptr<Context> context_;
  double setup_s_ = 0;
  Texture texture_;
  Texture fill_target_;  // the fragment pass's, kept for the run
  std::optional<Program> fill_program_;
  std::optional<FullscreenTriangle> triangle_;
  PixelBuffer unpack_, pack_;
  std::optional<PixelBuffer::Mapping> mapping_;  // the pack buffer, from a timed read-back's map
  std::uint32_t pass_ = 0;
};

}  // namespace

std::unique_ptr<LinkCopy::Bench> make_link_bench(const StrategyOptions& options) {
  return std::make_unique<LinkBench>(platform_option(options));
}

}  // namespace nurbs::gl
