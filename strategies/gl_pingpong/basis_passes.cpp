#include "strategies/gl_pingpong/basis_passes.h"

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <string_view>

#include "strategies/gl_pingpong/shaders.h"
#include "strategies/strategy.h"

namespace nurbs::gl_pingpong {
namespace {

std::string defines(bool packed) {
  return packed ? "#define PACKED 1\n" : "#define PACKED 0\n";
}

}  // namespace

BasisProgram::BasisProgram(gl::Context& context_, bool packed)
    : context(context_),
      program(context_, embedded::gl_fullscreen_triangle_vert,
              embedded::gl_pingpong_basis_order_frag, defines(packed),
              "gl-pingpong basis_order.frag"),
      degree(program.uniform("degree")),
      order(program.uniform("order")),
      basis_x0(program.uniform("basis_x0")),
      knot_x0(program.uniform("knot_x0")),
      triangle_(context_) {
  const gl::Functions& gl = context.gl();
  // Sampler units never change: set them once.
  gl.UseProgram(program.id());
  gl.Uniform1i(program.uniform("knot_array"), 0);
  gl.Uniform1i(program.uniform("previous"), 1);
  gl.UseProgram(0);
  context.check("gl-pingpong basis program");
}

void BasisProgram::draw() const {
  triangle_.draw();
}

Programs::Programs(gl::Context& context_, bool packed)
    : context(context_),
      basis(context_, packed),
      accumulate(context_, embedded::gl_fullscreen_triangle_vert,
                 embedded::gl_pingpong_accumulate_frag, defines(packed),
                 "gl-pingpong accumulate.frag"),
      divide(context_, embedded::gl_fullscreen_triangle_vert, embedded::gl_pingpong_divide_frag,
             defines(packed), "gl-pingpong divide.frag"),
      accumulate_a(accumulate.uniform("a")),
      accumulate_b(accumulate.uniform("b")),
      origin(accumulate.uniform("origin")),
      control_origin(accumulate.uniform("control_origin")),
      place_u(accumulate.uniform("place_u")),
      place_v(accumulate.uniform("place_v")) {
  const gl::Functions& gl = context.gl();
  gl.UseProgram(accumulate.id());
  gl.Uniform1i(accumulate.uniform("previous"), 0);
  gl.Uniform1i(accumulate.uniform("control"), 1);
  gl.Uniform1i(accumulate.uniform("basis_u"), 2);
  gl.Uniform1i(accumulate.uniform("basis_v"), 3);
  gl.Uniform1i(accumulate.uniform("first_u"), 4);
  gl.Uniform1i(accumulate.uniform("first_v"), 5);
  gl.UseProgram(divide.id());
  gl.Uniform1i(divide.uniform("sum"), 0);
  gl.UseProgram(0);
  context.check("gl-pingpong programs");
}

BasisChunk::BasisChunk(gl::Context& context, const ChunkInputs& in)
    : context_(&context),
      count_(in.count),
      rows_(in.rows),
      degree_(in.degree),
      knot_array_(context, in.packed ? GL_RGBA32F : GL_R32F, in.knot_array_width(), in.rows, false),
      order1_(context, GL_RGBA32F, in.basis_width(), in.rows, false),
      first_index_(context, GL_R32I, 1, in.count, false),
      first_indices_(in.first_index) {
  const GLenum format = in.packed ? GL_RGBA : GL_RED;
  const std::size_t texel = sizeof(float) * static_cast<std::size_t>(in.channels);
  bytes_uploaded_ += knot_array_.upload(format, GL_FLOAT, in.knot_array.data(), texel);
  bytes_uploaded_ += order1_.upload(format, GL_FLOAT, in.order1.data(), texel);
  bytes_uploaded_ +=
      first_index_.upload(GL_RED_INTEGER, GL_INT, in.first_index.data(), sizeof(std::int32_t));
  for (gl::Texture& t : ping_)
    t = gl::Texture(context, GL_RGBA32F, in.basis_width(), in.rows, true);
  result_ = &order1_;
  context.check("gl-pingpong basis upload");
}

void BasisChunk::raise(const BasisProgram& program, int passes) {
  const gl::Functions& gl = context_->gl();
  gl.UseProgram(program.program.id());
  gl.Uniform1i(program.order, degree_ + 1);
  gl.Uniform1i(program.basis_x0, 0);
  gl.Uniform1i(program.knot_x0, 0);
  knot_array_.bind_to_unit(0);
  const gl::Texture* source = &order1_;
  for (int pass = 0; pass < passes; ++pass) {
    const gl::Texture& target = ping_[pass % 2];
    target.bind_target();
    source->bind_to_unit(1);
    gl.Uniform1i(program.degree, pass + 1);
    program.draw();
    source = &target;
  }
  result_ = source;
}

std::vector<float> BasisChunk::read_result() const {
  const gl::Functions& gl = context_->gl();
  std::vector<float> out(static_cast<std::size_t>(result_->width()) * rows_ * 4);
  if (result_ == &order1_) {
    // Not a render target; only ever asked for after raise() by the tests.
    return {};
  }
  result_->bind_target();
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
  context_->read_pixels(0, 0, result_->width(), rows_, GL_RGBA, GL_FLOAT, out.data());
  context_->check("gl-pingpong basis read-back");
  return out;
}

BasisAtlas::BasisAtlas(gl::Context& context, const std::vector<ChunkInputs>& chunks, bool packed,
                       int side, std::size_t& bytes)
    : context_(&context) {
  const int channels = packed ? 4 : 1;
  for (const ChunkInputs& in : chunks) {
    basis_width_ = std::max(basis_width_, in.basis_width());
    knot_width_ = std::max(knot_width_, in.knot_array_width());
  }
  // Two row spaces: the basis textures' (a row per parameter, a quarter of that packed) and the
  // first-index texture's (a row per parameter).
  struct Bands {
    int side, band = 0, row = 0, height = 1;
    std::pair<int, int> place(int rows) {
      if (row + rows > side) {
        ++band;
        row = 0;
      }
      const std::pair<int, int> p{band, row};
      row += rows;
      height = std::max(height, row);
      return p;
    }
  };
  Bands basis{side}, index{side};
  for (const ChunkInputs& in : chunks) {
    const auto [band, row0] = basis.place(in.rows);
    const auto [first_band, first_row0] = index.place(in.count);
    places_.push_back({band, row0, in.rows, in.degree, first_band, first_row0});
  }
  const int bands = basis.band + 1, first_bands = index.band + 1, height = basis.height;
  if (static_cast<long long>(bands) * knot_width_ > context.max_texture_size() ||
      first_bands > context.max_texture_size())
    throw RefusedError(fmt::format(
        "{} bands of {} parameter rows need a knot-array texture {} texels wide, beyond "
        "GL_MAX_TEXTURE_SIZE {}",
        bands, side, static_cast<long long>(bands) * knot_width_, context.max_texture_size()));
  const std::size_t knot_w = static_cast<std::size_t>(bands) * knot_width_,
                    basis_w = static_cast<std::size_t>(bands) * basis_width_;
  std::vector<float> knots(knot_w * height * channels, 0.0f),
      order1(basis_w * height * channels, 0.0f);
  std::vector<std::int32_t> first(static_cast<std::size_t>(first_bands) * index.height, 0);
  for (std::size_t c = 0; c < chunks.size(); ++c) {
    const ChunkInputs& in = chunks[c];
    const Place& p = places_[c];
    const std::size_t kw = static_cast<std::size_t>(in.knot_array_width()) * channels,
                      bw = static_cast<std::size_t>(in.basis_width()) * channels;
    for (int r = 0; r < in.rows; ++r) {
      const std::size_t y = static_cast<std::size_t>(p.row0 + r);
      std::copy_n(&in.knot_array[static_cast<std::size_t>(r) * kw], kw,
                  &knots[(y * knot_w + static_cast<std::size_t>(p.band) * knot_width_) * channels]);
      std::copy_n(
          &in.order1[static_cast<std::size_t>(r) * bw], bw,
          &order1[(y * basis_w + static_cast<std::size_t>(p.band) * basis_width_) * channels]);
    }
    for (int q = 0; q < in.count; ++q)
      first[static_cast<std::size_t>(p.first_row0 + q) * first_bands + p.first_band] =
          in.first_index[static_cast<std::size_t>(q)];
  }
  const GLenum format = packed ? GL_RGBA : GL_RED;
  const std::size_t texel = sizeof(float) * static_cast<std::size_t>(channels);
  knot_array_ =
      gl::Texture(context, packed ? GL_RGBA32F : GL_R32F, static_cast<int>(knot_w), height, false);
  bytes += knot_array_.upload(format, GL_FLOAT, knots.data(), texel);
  order1_ = gl::Texture(context, GL_RGBA32F, static_cast<int>(basis_w), height, false);
  bytes += order1_.upload(format, GL_FLOAT, order1.data(), texel);
  first_index_ = gl::Texture(context, GL_R32I, first_bands, index.height, false);
  bytes += first_index_.upload(GL_RED_INTEGER, GL_INT, first.data(), sizeof(std::int32_t));
  for (gl::Texture& t : ping_)
    t = gl::Texture(context, GL_RGBA32F, static_cast<int>(basis_w), height, true);
}

void BasisAtlas::raise(const BasisProgram& program, std::size_t c, int passes) const {
  const gl::Functions& gl = context_->gl();
  const Place& p = places_[c];
  gl.UseProgram(program.program.id());
  gl.Uniform1i(program.order, p.degree + 1);
  gl.Uniform1i(program.basis_x0, p.band * basis_width_);
  gl.Uniform1i(program.knot_x0, p.band * knot_width_);
  knot_array_.bind_to_unit(0);
  const gl::Texture* source = &order1_;
  for (int pass = 0; pass < passes; ++pass) {
    const gl::Texture& target = ping_[pass % 2];
    target.bind_target();
    gl.Viewport(p.band * basis_width_, p.row0, p.degree + 2, p.rows);
    source->bind_to_unit(1);
    gl.Uniform1i(program.degree, pass + 1);
    program.draw();
    source = &target;
  }
}

const gl::Texture& BasisAtlas::result(std::size_t c) const {
  const int passes = places_[c].degree;
  return passes == 0 ? order1_ : ping_[(passes - 1) % 2];
}

std::vector<BasisChunk> upload_chunks(gl::Context& context, const std::vector<double>& parameters,
                                      int degree, int count, const std::vector<float>& knots,
                                      bool packed, int tile, std::vector<std::size_t>& begins,
                                      std::size_t& bytes) {
  std::vector<BasisChunk> chunks;
  const std::size_t step = static_cast<std::size_t>(tile);
  for (std::size_t begin = 0; begin < parameters.size(); begin += step) {
    const std::size_t end = std::min(parameters.size(), begin + step);
    chunks.emplace_back(context,
                        make_chunk_inputs(parameters, begin, end, degree, count, knots, packed));
    bytes += chunks.back().bytes_uploaded();
    begins.push_back(begin);
  }
  return chunks;
}

}  // namespace nurbs::gl_pingpong
