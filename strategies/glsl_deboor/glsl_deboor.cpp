#include "strategies/glsl_deboor/glsl_deboor.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

#include "reference/validation.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_context/grid_renderer.h"
#include "strategies/glsl_deboor/deboor_evaluator.h"
#include "strategies/glsl_deboor/renderer.h"
#include "strategies/strategy_options.h"
#include "strategies/trim_texture/trim_texture.h"

namespace nurbs {
namespace {

// The image the render phases draw (the size of 002's §4.2 timings is not given; 512² keeps the
// raster cost visible next to the evaluation without dominating it).
constexpr int kRenderSize = 512;

// Option deboor-draw: per-span (default, 002's form) or instanced.
glsl_deboor::DrawMode draw_option(const StrategyOptions& options) {
  const auto it = options.extra.find("deboor-draw");
  if (it == options.extra.end() || it->second.empty() || it->second == "per-span")
    return glsl_deboor::DrawMode::per_span;
  if (it->second == "instanced") return glsl_deboor::DrawMode::instanced;
  throw std::invalid_argument(fmt::format(
      "glsl-deboor option deboor-draw = '{}': must be per-span or instanced", it->second));
}

class GlslDeBoor final : public Strategy {
 public:
  GlslDeBoor(gl::Platform platform, int tile_option, const trim_texture::Options& trim_options,
             glsl_deboor::DrawMode draw)
      : draw_(draw) {
    try {
      context_ = gl::Context::create(platform);
    } catch (const gl::UnavailableError& e) {
      throw std::runtime_error(fmt::format("unavailable: {}", e.what()));
    }
    timer_ = std::make_unique<gl::DeviceTimer>(*context_);
    tile_ = std::min(context_->max_texture_size(), context_->max_viewport());
    if (tile_option > 0) tile_ = std::min(tile_, tile_option);
    evaluator_ = std::make_unique<glsl_deboor::Evaluator>(*context_, tile_, draw_);
    trims_ = std::make_unique<trim_texture::TrimTextures>(*context_, trim_options, "glsl-deboor");
  }

  ~GlslDeBoor() override {
    context_->make_current();
    renderer_.reset();
    trims_.reset();
    evaluator_.reset();
  }

  std::string_view name() const override { return "glsl-deboor"; }
  Capabilities capabilities() const override { return glsl_deboor_descriptor().capabilities; }

  DeviceInfo device() const override {
    DeviceInfo d = context_->device_info();
    d.details["tile"] = std::to_string(tile_);
    d.details["pages"] = std::to_string(evaluator_->pages().size());
    // The draw mode tells a per-span record from an instanced one (the report labels them apart).
    d.details["draw"] = draw_ == glsl_deboor::DrawMode::instanced ? "instanced" : "per-span";
    // Counted from the draws the last evaluate() issued (gl::DrawCounts), 0 before one: a pass is
    // one target drawn into; per span a quad is one draw, instanced one instance.
    d.details["quads"] = std::to_string(evaluated_quads_);
    d.details["draws"] = std::to_string(evaluated_.draws);
    d.details["passes"] = std::to_string(evaluated_.passes);
    d.details["bytes_uploaded"] = std::to_string(bytes_uploaded_);
    if (bytes_updated_) d.details["bytes_updated"] = std::to_string(bytes_updated_);
    trims_->add_details(d);
    return d;
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    samples_ = sample_parameters(scene, request.sampling);
    view_ = gl::orthographic_view(scene);
    context_->make_current();
    evaluated_ = {};
    evaluated_quads_ = 0;
    bytes_updated_ = 0;
    times_.upload_s = timer_->time("glsl-deboor upload", [&] {
      bytes_uploaded_ = evaluator_->prepare(scene, samples_);
      trims_->prepare(scene, samples_);
    });
  }

  // The trim textures stay: a deforming scene moves points, never trims or samples.
  void update_control_points(const Scene& scene) override {
    times_.upload_s = timer_->time("glsl-deboor control point update", [&] {
      bytes_updated_ = evaluator_->update_control_points(scene);
    });
    view_ = gl::orthographic_view(scene);  // as prepare() would frame the moved scene
  }

  void evaluate() override {
    const gl::DrawCounts before = context_->draw_counts();
    times_.evaluate_s =
        timer_->time("glsl-deboor evaluate", [&] { evaluated_quads_ = evaluator_->evaluate(); });
    evaluated_ = context_->draw_counts() - before;
  }

  DeviceTimes device_times() const override { return times_; }

  bool render() override {
    context_->make_current();
    renderer().draw_without_read_back(*evaluator_, view_.data(), trims_.get());
    context_->finish("glsl-deboor render");
    context_->check("glsl-deboor render");
    return true;
  }

  std::optional<RenderedImage> last_render() override {
    return gl::last_picture(*context_, renderer_ ? &renderer_->grid() : nullptr);
  }

  bool classify() override { return trims_->classify(); }

  bool render_via_read_back() override {
    context_->make_current();
    renderer().draw_with_read_back(*evaluator_, view_.data(), trims_.get());
    context_->finish("glsl-deboor render via read-back");
    context_->check("glsl-deboor render via read-back");
    return true;
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  void read_back_into(EvalResult& out) override {
    context_->make_current();
    evaluator_->read_back_into(out);
    times_.read_back_s = evaluator_->read_back_device_s();
    for (std::size_t i = 0; i < out.surfaces.size(); ++i)
      out.surfaces[i].inside = trims_->read_mask(i);
  }

 private:
  // Created at the first draw: a run that never renders allocates no framebuffer.
  glsl_deboor::Renderer& renderer() {
    if (!renderer_)
      renderer_ = std::make_unique<glsl_deboor::Renderer>(*context_, kRenderSize, kRenderSize);
    return *renderer_;
  }

  std::unique_ptr<gl::Context> context_;
  std::unique_ptr<gl::DeviceTimer> timer_;
  std::unique_ptr<glsl_deboor::Evaluator> evaluator_;
  std::unique_ptr<trim_texture::TrimTextures> trims_;
  std::unique_ptr<glsl_deboor::Renderer> renderer_;
  std::array<float, 16> view_{};
  int tile_ = 0;
  std::vector<SurfaceSamples> samples_;
  DeviceTimes times_;  // each phase's last device time (device_times())
  std::size_t bytes_uploaded_ = 0, bytes_updated_ = 0;
  glsl_deboor::DrawMode draw_;
  gl::DrawCounts evaluated_;  // by the last evaluate()
  std::size_t evaluated_quads_ = 0;
};

}  // namespace

StrategyEntry glsl_deboor_entry() {
  return make_entry(
      glsl_deboor_descriptor(), gl::Context::probe_any,
      [](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
        return std::make_unique<GlslDeBoor>(
            gl::platform_option(options), positive_option(options, "tile", "glsl-deboor"),
            trim_texture::parse_options(options, "glsl-deboor"), draw_option(options));
      });
}

}  // namespace nurbs
