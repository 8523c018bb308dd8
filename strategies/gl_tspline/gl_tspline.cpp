#include "strategies/gl_tspline/gl_tspline.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <stdexcept>
#include <tuple>

#include "reference/tspline.h"
#include "reference/validation.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_context/gl_program.h"
#include "strategies/gl_tspline/region_tables.h"
#include "strategies/host_results.h"
#include "strategies/strategy_options.h"

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
extern const std::string_view gl_tspline_accumulate_frag;
extern const std::string_view gl_tspline_divide_frag;
extern const std::string_view gl_tspline_local_basis_h;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

using gl_tspline::kLinearWidth;

constexpr const char* kName = "gl-tspline";
// One bicubic region of a tensor-product mesh (16 points) per pass; T-junction regions of
// bicubic T-splines take two.
constexpr int kDefaultPointsPerPass = 16;

// Texture units of the passes' samplers.
enum Unit : int {
  kPreviousSum,
  kPreviousSu,
  kPreviousSv,
  kPoints,
  kKnotsU,
  kKnotsV,
  kOffsets,
  kActive,
  kParameters,
  kRegions
};

// accumulate.frag and divide.frag compiled for one degree pair, split and normals choice.
struct PassPrograms {
  PassPrograms(gl::Context& context, int degree_u, int degree_v, int points_per_pass, bool normals)
      : accumulate(
            context, embedded::gl_fullscreen_triangle_vert, embedded::gl_tspline_accumulate_frag,
            defines(degree_u, degree_v, points_per_pass, normals), "gl-tspline accumulate.frag"),
        divide(context, embedded::gl_fullscreen_triangle_vert, embedded::gl_tspline_divide_frag,
               defines(degree_u, degree_v, points_per_pass, normals), "gl-tspline divide.frag"),
        first(accumulate.uniform("first")) {
    const gl::Functions& gl = context.gl();
    // Sampler units never change: set once per program.
    gl.UseProgram(accumulate.id());
    gl.Uniform1i(accumulate.uniform("previous_sum"), kPreviousSum);
    if (normals) {
      gl.Uniform1i(accumulate.uniform("previous_su"), kPreviousSu);
      gl.Uniform1i(accumulate.uniform("previous_sv"), kPreviousSv);
    }
    gl.Uniform1i(accumulate.uniform("points"), kPoints);
    gl.Uniform1i(accumulate.uniform("knots_u"), kKnotsU);
    gl.Uniform1i(accumulate.uniform("knots_v"), kKnotsV);
    gl.Uniform1i(accumulate.uniform("offsets"), kOffsets);
    gl.Uniform1i(accumulate.uniform("entries"), kActive);
    gl.Uniform1i(accumulate.uniform("parameters"), kParameters);
    gl.Uniform1i(accumulate.uniform("regions"), kRegions);
    gl.UseProgram(divide.id());
    gl.Uniform1i(divide.uniform("sum"), kPreviousSum);
    if (normals) {
      gl.Uniform1i(divide.uniform("sum_u"), kPreviousSu);
      gl.Uniform1i(divide.uniform("sum_v"), kPreviousSv);
    }
    gl.UseProgram(0);
    context.check("gl-tspline programs");
  }

  // The program's constants, then the single-source local basis (GL 3.3 GLSL has no #include).
  static std::string defines(int degree_u, int degree_v, int points_per_pass, bool normals) {
    return fmt::format(
               "#define DEGREE_U {}\n#define DEGREE_V {}\n#define LB_MAX_DEGREE {}\n"
               "#define POINTS_PER_PASS {}\n#define NORMALS {}\n#define LINEAR_WIDTH {}\n",
               degree_u, degree_v, std::max(degree_u, degree_v), points_per_pass, normals ? 1 : 0,
               kLinearWidth) +
           std::string(embedded::gl_tspline_local_basis_h);
  }

  gl::Program accumulate, divide;
  GLint first;
};

struct SurfaceOnGpu {
  const PassPrograms* programs = nullptr;
  int accumulation_passes = 0;
  std::size_t count = 0;  // samples
  std::size_t control_points = 0;
  gl::Texture points, knots_u, knots_v, offsets, active, parameters, regions;
  gl::RenderTargets sums[2];  // 001's tex1 / tex2, with the derivative sums beside the sum
  gl::RenderTargets output;   // position (and normal)
};

class GlTSpline final : public Strategy {
 public:
  GlTSpline(gl::Platform platform, int points_per_pass) : points_per_pass_(points_per_pass) {
    try {
      context_ = gl::Context::create(platform);
    } catch (const gl::UnavailableError& e) {
      throw std::runtime_error(fmt::format("unavailable: {}", e.what()));
    }
    timer_ = std::make_unique<gl::DeviceTimer>(*context_);
    triangle_ = std::make_unique<gl::FullscreenTriangle>(*context_);
    results_ = gl::PixelBuffer(*context_, GL_STREAM_READ);
  }

  ~GlTSpline() override {
    context_->make_current();
    surfaces_.clear();
    programs_.clear();
    triangle_.reset();
    results_ = gl::PixelBuffer();
  }

  std::string_view name() const override { return kName; }
  Capabilities capabilities() const override { return gl_tspline_descriptor().capabilities; }

  DeviceInfo device() const override {
    DeviceInfo d = context_->device_info();
    d.details["points_per_pass"] = std::to_string(points_per_pass_);
    d.details["passes"] = std::to_string(draws_);
    d.details["accumulation_passes"] = std::to_string(accumulation_passes_);
    d.details["max_active_points"] = std::to_string(max_active_);
    d.details["regions"] = std::to_string(regions_);
    d.details["bytes_uploaded"] = std::to_string(bytes_uploaded_);
    return d;
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    samples_ = sample_parameters(scene, request.sampling);
    normals_ = request.normals;
    context_->make_current();
    surfaces_.clear();
    bytes_uploaded_ = 0;
    accumulation_passes_ = regions_ = draws_ = 0;
    max_active_ = 0;
    times_.upload_s = timer_->time("gl-tspline upload", [&] {
      for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
        surfaces_.push_back(upload_surface(scene.surfaces[i], samples_[i]));
    });
  }

  // `passes` is what the context counted: render targets the last evaluate() drew into.
  void evaluate() override {
    const gl::DrawCounts before = context_->draw_counts();
    times_.evaluate_s = timer_->time("gl-tspline evaluate", [&] {
      for (SurfaceOnGpu& s : surfaces_) evaluate_surface(s);
    });
    draws_ = static_cast<std::size_t>((context_->draw_counts() - before).passes);
  }

  DeviceTimes device_times() const override { return times_; }

  // Moved points (same T-splines otherwise: knots, weights' count, samples): the region tables,
  // knots and sample textures of prepare() stay; only the homogeneous points are re-uploaded.
  void update_control_points(const Scene& scene) override {
    if (scene.surfaces.size() != surfaces_.size())
      throw std::invalid_argument(
          fmt::format("{}: update_control_points with {} surfaces, prepared with {}", kName,
                      scene.surfaces.size(), surfaces_.size()));
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const Surface& surface = scene.surfaces[i];
      if (!surface.is_tspline() || surface.tspline->count() != surfaces_[i].control_points)
        throw std::invalid_argument(
            fmt::format("{}: update_control_points: surface '{}' is not the prepared T-spline",
                        kName, surface.name));
    }
    times_.upload_s = timer_->time("gl-tspline update", [&] {
      for (std::size_t i = 0; i < surfaces_.size(); ++i) {
        const std::vector<float> points =
            gl_tspline::homogeneous_points(*scene.surfaces[i].tspline);
        surfaces_[i].points.upload(GL_RGBA, GL_FLOAT, points.data(), sizeof(float) * 4);
      }
    });
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  // Output texel k is sample k (make_sample_table's layout): a surface's positions are its whole
  // rows and the start of one more, read as x y z (GL_RGB: the driver drops w) into one
  // pixel-pack buffer, every surface back to back, the normals after all the positions; the buffer
  // is mapped once and copied into the results.
  void read_back_into(EvalResult& out) override {
    context_->make_current();
    std::size_t points = 0;
    for (const SurfaceOnGpu& s : surfaces_) points += s.count;
    const std::size_t block = points * 3 * sizeof(float);
    const std::size_t bytes = block * (normals_ ? 2 : 1);
    if (bytes == 0) {
      shape_results(out, samples_, Precision::f32, normals_);
      return;
    }
    results_.reserve(bytes);
    times_.read_back_s = timer_->time("gl-tspline read-back", [&] {
      std::size_t first = 0;  // the surface's first point in the block
      for (const SurfaceOnGpu& s : surfaces_) {
        for (int target = 0; target < (normals_ ? 2 : 1); ++target)
          read_rows(s, target,
                    static_cast<std::size_t>(target) * block + first * 3 * sizeof(float));
        first += s.count;
      }
    });
    gl::PixelBuffer::Mapping mapped = results_.map_read(bytes, "gl-tspline read-back");
    const float* xyz = static_cast<const float*>(mapped.data());
    scatter_points(out, samples_, xyz, normals_ ? xyz + 3 * points : nullptr);
    mapped.release();
    context_->check("gl-tspline read-back");
  }

 private:
  // Samples [0, count) of render target `target` into the results buffer from byte `offset`
  // (glReadPixels returns rows bottom up, as gl_FragCoord counts them).
  void read_rows(const SurfaceOnGpu& s, int target, std::size_t offset) {
    if (s.count == 0) return;
    s.output.bind_target();
    context_->gl().ReadBuffer(static_cast<GLenum>(GL_COLOR_ATTACHMENT0 + target));
    const std::size_t width = static_cast<std::size_t>(s.output.texture(0).width());
    const std::size_t rows = s.count / width, rest = s.count % width;
    if (rows > 0)
      results_.read_pixels(offset, 0, 0, static_cast<GLsizei>(width), static_cast<GLsizei>(rows),
                           GL_RGB);
    if (rest > 0)
      results_.read_pixels(offset + rows * width * 3 * sizeof(float), 0, static_cast<GLint>(rows),
                           static_cast<GLsizei>(rest), 1, GL_RGB);
  }

  const PassPrograms& programs(int degree_u, int degree_v) {
    auto& p = programs_[{degree_u, degree_v, normals_}];
    if (!p)
      p = std::make_unique<PassPrograms>(*context_, degree_u, degree_v, points_per_pass_, normals_);
    return *p;
  }

  // A linear texture (region_tables.h) of `values`, already padded to whole rows.
  template <typename T>
  gl::Texture linear_texture(GLenum internal_format, GLenum format, GLenum type,
                             const std::vector<T>& values, int channels, const std::string& surface,
                             const char* what) {
    const std::size_t texels = values.size() / static_cast<std::size_t>(channels);
    const int rows = static_cast<int>(texels / kLinearWidth);
    if (rows > context_->max_texture_size())
      throw RefusedError(fmt::format(
          "{}: surface '{}': {} needs {} rows of {} texels, beyond GL_MAX_TEXTURE_SIZE {}", kName,
          surface, what, rows, kLinearWidth, context_->max_texture_size()));
    gl::Texture t(*context_, internal_format, kLinearWidth, rows, false);
    bytes_uploaded_ += t.upload(format, type, values.data(), sizeof(T) * channels);
    return t;
  }

  SurfaceOnGpu upload_surface(const Surface& surface, const SurfaceSamples& samples) {
    const TSplineSurface& ts = *surface.tspline;
    const TSplineInfluence index(ts, surface.name);
    const gl_tspline::RegionTables tables = gl_tspline::make_region_tables(ts, index);
    const gl_tspline::SampleTable table = gl_tspline::make_sample_table(index, samples);
    const int side = std::min(context_->max_texture_size(), context_->max_viewport());
    if (table.height > side)
      throw RefusedError(fmt::format(
          "{}: surface '{}': {} samples need {} rows of {} fragments, beyond the {} a texture "
          "or viewport allows",
          kName, surface.name, table.count, table.height, table.width, side));
    SurfaceOnGpu s;
    s.programs = &programs(ts.degree_u, ts.degree_v);
    s.count = table.count;
    s.control_points = ts.count();
    s.accumulation_passes = gl_tspline::accumulation_passes(tables.max_active, points_per_pass_);
    s.points = linear_texture(GL_RGBA32F, GL_RGBA, GL_FLOAT, tables.homogeneous, 4, surface.name,
                              "the control points");
    s.knots_u = linear_texture(GL_R32F, GL_RED, GL_FLOAT, tables.knots_u, 1, surface.name,
                               "the local u knots");
    s.knots_v = linear_texture(GL_R32F, GL_RED, GL_FLOAT, tables.knots_v, 1, surface.name,
                               "the local v knots");
    s.offsets = linear_texture(GL_R32I, GL_RED_INTEGER, GL_INT, tables.offsets, 1, surface.name,
                               "the region offsets");
    s.active = linear_texture(GL_RGBA32I, GL_RGBA_INTEGER, GL_INT, tables.active, 4, surface.name,
                              "the region lists");
    s.parameters = gl::Texture(*context_, GL_RG32F, table.width, table.height, false);
    bytes_uploaded_ += s.parameters.upload(GL_RG, GL_FLOAT, table.uv.data(), sizeof(float) * 2);
    s.regions = gl::Texture(*context_, GL_R32I, table.width, table.height, false);
    bytes_uploaded_ +=
        s.regions.upload(GL_RED_INTEGER, GL_INT, table.regions.data(), sizeof(std::int32_t));
    const int sums = normals_ ? 3 : 1;
    for (gl::RenderTargets& t : s.sums)
      t = gl::RenderTargets(*context_, GL_RGBA32F, table.width, table.height, sums);
    s.output =
        gl::RenderTargets(*context_, GL_RGBA32F, table.width, table.height, normals_ ? 2 : 1);
    accumulation_passes_ += static_cast<std::size_t>(s.accumulation_passes);
    max_active_ = std::max(max_active_, tables.max_active);
    regions_ += tables.regions;
    return s;
  }

  void bind_sums(const gl::RenderTargets& sums) const {
    for (int i = 0; i < sums.count(); ++i) sums.texture(i).bind_to_unit(kPreviousSum + i);
  }

  void evaluate_surface(SurfaceOnGpu& s) {
    const gl::Functions& gl = context_->gl();
    s.points.bind_to_unit(kPoints);
    s.knots_u.bind_to_unit(kKnotsU);
    s.knots_v.bind_to_unit(kKnotsV);
    s.offsets.bind_to_unit(kOffsets);
    s.active.bind_to_unit(kActive);
    s.parameters.bind_to_unit(kParameters);
    s.regions.bind_to_unit(kRegions);
    s.sums[0].bind_target();  // tex1 starts at zero
    gl.ClearColor(0, 0, 0, 0);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    gl.UseProgram(s.programs->accumulate.id());
    int current = 0;
    for (int pass = 0; pass < s.accumulation_passes; ++pass) {
      s.sums[1 - current].bind_target();
      bind_sums(s.sums[current]);
      gl.Uniform1i(s.programs->first, pass * points_per_pass_);
      triangle_->draw();
      current = 1 - current;
    }
    gl.UseProgram(s.programs->divide.id());
    s.output.bind_target();
    bind_sums(s.sums[current]);
    triangle_->draw();
  }

  int points_per_pass_;
  bool normals_ = false;
  std::unique_ptr<gl::Context> context_;
  std::unique_ptr<gl::DeviceTimer> timer_;
  std::unique_ptr<gl::FullscreenTriangle> triangle_;
  std::map<std::tuple<int, int, bool>, std::unique_ptr<PassPrograms>> programs_;
  std::vector<SurfaceSamples> samples_;
  std::vector<SurfaceOnGpu> surfaces_;
  gl::PixelBuffer results_;  // read-backs land here; grown, never shrunk
  DeviceTimes times_;        // each phase's last device time (device_times())
  std::size_t bytes_uploaded_ = 0, accumulation_passes_ = 0, regions_ = 0, draws_ = 0;
  int max_active_ = 0;
};

}  // namespace

StrategyEntry gl_tspline_entry() {
  return make_entry(gl_tspline_descriptor(), gl::Context::probe_any,
                    [](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
                      const int points = positive_option(options, "tspline-points-per-pass", kName);
                      return std::make_unique<GlTSpline>(
                          gl::platform_option(options),
                          points > 0 ? points : kDefaultPointsPerPass);
                    });
}

}  // namespace nurbs
