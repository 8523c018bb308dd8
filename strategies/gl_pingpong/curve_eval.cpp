#include "strategies/gl_pingpong/curve_eval.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "reference/validation.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_pingpong/basis_passes.h"
#include "strategies/gl_pingpong/shaders.h"
#include "strategies/strategy_options.h"

namespace nurbs::gl_pingpong {

std::string_view to_string(Reduction reduction) {
  return reduction == Reduction::pairwise ? "pairwise" : "single-pass";
}

namespace {

constexpr std::string_view kName = "gl-pingpong curve";

// Texels each reduction pass sums per output texel, and the widths the passes write: k -> 1.
std::vector<int> reduction_widths(int order, Reduction reduction) {
  std::vector<int> widths;
  if (reduction == Reduction::single_pass) return {1};
  for (int w = order; w > 1;) {
    w = (w + 1) / 2;
    widths.push_back(w);
  }
  return widths;
}

// One chunk of at most `tile` parameters: its basis passes' textures, the width-k control array,
// the product, the reduction stages and the divided result (width 1).
struct CurveChunk {
  BasisChunk basis;
  gl::Texture control, product;
  std::vector<gl::Texture> stages;
  gl::Texture points;
};

}  // namespace

struct CurveEvaluator::Impl {
  Impl(const StrategyOptions& options, Reduction reduction_)
      : reduction(reduction_),
        context(create_context(options)),
        timer(*context),
        basis(*context, false),
        multiply(*context, embedded::gl_fullscreen_triangle_vert,
                 embedded::gl_pingpong_multiply_frag, "", "gl-pingpong multiply.frag"),
        reduce(*context, embedded::gl_fullscreen_triangle_vert, embedded::gl_pingpong_reduce_frag,
               "", "gl-pingpong reduce.frag"),
        divide(*context, embedded::gl_fullscreen_triangle_vert, embedded::gl_pingpong_divide_frag,
               "", "gl-pingpong divide.frag"),
        reduce_width(reduce.uniform("width")),
        reduce_group(reduce.uniform("group")) {
    tile = std::min(context->max_texture_size(), context->max_viewport());
    if (const int t = positive_option(options, "tile", kName); t > 0) tile = std::min(tile, t);
    const gl::Functions& gl = context->gl();
    gl.UseProgram(multiply.id());
    gl.Uniform1i(multiply.uniform("basis"), 0);
    gl.Uniform1i(multiply.uniform("control"), 1);
    gl.UseProgram(reduce.id());
    gl.Uniform1i(reduce.uniform("partial"), 0);
    gl.UseProgram(divide.id());
    gl.Uniform1i(divide.uniform("sum"), 0);
    gl.UseProgram(0);
    context->check("gl-pingpong curve programs");
  }

  ~Impl() {
    context->make_current();
    chunks.clear();
    results = gl::PixelBuffer();
  }

  static std::unique_ptr<gl::Context> create_context(const StrategyOptions& options) {
    try {
      return gl::Context::create(gl::platform_option(options));
    } catch (const gl::UnavailableError& e) {
      throw std::runtime_error(fmt::format("unavailable: {}", e.what()));
    }
  }

  void evaluate_chunk(CurveChunk& c) {
    const gl::Functions& gl = context->gl();
    gl::DrawCounts mark = context->draw_counts();
    auto count_into = [&](std::uint64_t& counter) {
      const gl::DrawCounts now = context->draw_counts();
      counter += (now - mark).passes;
      mark = now;
    };
    // §2.1: k-1 passes.
    c.basis.raise(basis, degree);
    count_into(passes.basis);
    // §2.2: basis x control points over the width-k array.
    gl.UseProgram(multiply.id());
    c.product.bind_target();
    c.basis.result().bind_to_unit(0);
    c.control.bind_to_unit(1);
    basis.draw();
    count_into(passes.multiply);
    // §2.2: the per-row sum.
    gl.UseProgram(reduce.id());
    gl.Uniform1i(reduce_group, reduction == Reduction::pairwise ? 2 : degree + 1);
    const gl::Texture* source = &c.product;
    for (const gl::Texture& stage : c.stages) {
      stage.bind_target();
      source->bind_to_unit(0);
      gl.Uniform1i(reduce_width, source->width());
      basis.draw();
      source = &stage;
    }
    count_into(passes.reduction);
    // Rational: (x, y, z) / w at the end, as the surface path's last pass.
    gl.UseProgram(divide.id());
    c.points.bind_target();
    source->bind_to_unit(0);
    basis.draw();
    count_into(passes.divide);
  }

  Reduction reduction;
  std::unique_ptr<gl::Context> context;
  gl::DeviceTimer timer;
  BasisProgram basis;
  gl::Program multiply, reduce, divide;
  GLint reduce_width, reduce_group;
  int tile = 0, degree = 0;
  std::size_t parameter_count = 0, bytes_uploaded = 0;
  std::vector<CurveChunk> chunks;
  std::vector<std::size_t> begins;
  gl::PixelBuffer results{*context, GL_STREAM_READ};  // read-backs land here; grown, never shrunk
  CurvePasses passes;
  double device_seconds = 0;
};

CurveEvaluator::CurveEvaluator(const StrategyOptions& options, Reduction reduction)
    : impl_(std::make_unique<Impl>(options, reduction)) {}

CurveEvaluator::~CurveEvaluator() = default;

void CurveEvaluator::prepare(const Curve& curve, const std::vector<double>& parameters) {
  validate_curve(curve, kName);
  for (std::size_t i = 0; i < parameters.size(); ++i)
    if (!std::isfinite(parameters[i]))
      throw InputError(fmt::format("{}: parameters[{}] = {}: parameters must be finite", kName, i,
                                   format_number(parameters[i])));
  Impl& m = *impl_;
  m.context->make_current();
  m.chunks.clear();
  m.begins.clear();
  m.bytes_uploaded = 0;
  m.passes = {};
  m.degree = curve.degree;
  m.parameter_count = parameters.size();
  const int order = curve.degree + 1;
  const std::vector<float> knots(curve.knots.begin(), curve.knots.end());
  std::vector<BasisChunk> bases = upload_chunks(*m.context, parameters, curve.degree, curve.count(),
                                                knots, false, m.tile, m.begins, m.bytes_uploaded);
  const std::vector<int> widths = reduction_widths(order, m.reduction);
  std::vector<float> gathered;
  for (BasisChunk& b : bases) {
    const int rows = b.count();
    // §2.2: "another array with the corresponding control points for each parameter value ... is
    // created on the CPU": row q holds P_{s-p} .. P_s of parameter q, x, y, z, w in RGBA.
    gathered.assign(static_cast<std::size_t>(rows) * order * 4, 0.0f);
    for (int q = 0; q < rows; ++q)
      for (int j = 0; j < order; ++j) {
        const Vec4<double>& p =
            curve.homogeneous[static_cast<std::size_t>(b.first_indices()[q] + j)];
        for (int c = 0; c < 4; ++c)
          gathered[(static_cast<std::size_t>(q) * order + j) * 4 + c] = static_cast<float>(p[c]);
      }
    CurveChunk c{std::move(b),
                 gl::Texture(*m.context, GL_RGBA32F, order, rows, false),
                 gl::Texture(*m.context, GL_RGBA32F, order, rows, true),
                 {},
                 gl::Texture(*m.context, GL_RGBA32F, 1, rows, true)};
    m.bytes_uploaded += c.control.upload(GL_RGBA, GL_FLOAT, gathered.data(), sizeof(float) * 4);
    for (int w : widths) c.stages.emplace_back(*m.context, GL_RGBA32F, w, rows, true);
    m.chunks.push_back(std::move(c));
  }
  m.context->finish("gl-pingpong curve upload");
  m.context->check("gl-pingpong curve upload");
}

void CurveEvaluator::evaluate() {
  Impl& m = *impl_;
  m.passes = {};
  m.device_seconds = m.timer.time("gl-pingpong curve evaluate", [&] {
    for (CurveChunk& c : m.chunks) m.evaluate_chunk(c);
  });
}

// Each chunk's column of points read as x y z (GL_RGB: the driver drops w) into its place in one
// pixel-pack buffer, mapped once and copied out.
std::vector<Vec3<float>> CurveEvaluator::read_back() {
  static_assert(sizeof(Vec3<float>) == 3 * sizeof(float));
  Impl& m = *impl_;
  m.context->make_current();
  const gl::Functions& gl = m.context->gl();
  std::vector<Vec3<float>> out(m.parameter_count);
  const std::size_t bytes = m.parameter_count * sizeof(Vec3<float>);
  if (bytes == 0) return out;
  m.results.reserve(bytes);
  for (std::size_t i = 0; i < m.chunks.size(); ++i) {
    const gl::Texture& points = m.chunks[i].points;
    points.bind_target();
    gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    m.results.read_pixels(m.begins[i] * sizeof(Vec3<float>), 0, 0, 1, points.height(), GL_RGB);
  }
  gl::PixelBuffer::Mapping mapped = m.results.map_read(bytes, "gl-pingpong curve read-back");
  std::memcpy(out.data(), mapped.data(), bytes);
  mapped.release();
  m.context->check("gl-pingpong curve read-back");
  return out;
}

CurvePasses CurveEvaluator::passes() const {
  return impl_->passes;
}
double CurveEvaluator::device_seconds() const {
  return impl_->device_seconds;
}
std::size_t CurveEvaluator::bytes_uploaded() const {
  return impl_->bytes_uploaded;
}
int CurveEvaluator::tile() const {
  return impl_->tile;
}

}  // namespace nurbs::gl_pingpong
