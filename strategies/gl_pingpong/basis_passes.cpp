#include "strategies/gl_pingpong/basis_passes.h"

#include <algorithm>
#include <string>
#include <string_view>

#include "strategies/gl_pingpong/shaders.h"

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
      accumulate_b(accumulate.uniform("b")) {
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
