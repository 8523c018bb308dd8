#include "strategies/gl_pingpong/gl_pingpong.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cstdint>
#include <stdexcept>

#include "reference/nurbs_math.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_context/grid_renderer.h"
#include "strategies/gl_pingpong/basis_passes.h"
#include "strategies/gl_pingpong/lod_renderer.h"
#include "strategies/strategy_options.h"
#include "strategies/trim_texture/trim_texture.h"

namespace nurbs {
namespace {

using gl_pingpong::BasisChunk;
using gl_pingpong::Programs;

// The image the render phases draw: glsl-deboor's size, so the two compare.
constexpr int kRenderSize = 512;

// One tile of the evaluation grid: u-chunk cu x v-chunk cv, its running sum ping-pongs between
// sum[0] and sum[1] (the paper's tex1/tex2); `result` is where the divide pass wrote the points.
struct Tile {
  int cu = 0, cv = 0;
  gl::Texture sum[2];
  int result = 0;
};

struct SurfaceOnGpu {
  int degree_u = 0, degree_v = 0, count_u = 0, count_v = 0;
  gl::Texture control;                  // count_v x count_u homogeneous control points (000 §3.1)
  std::vector<float> knots_u, knots_v;  // kept for a new grid (000 §3.2's LOD)
  std::vector<BasisChunk> u_chunks, v_chunks;
  std::vector<std::size_t> u_begin, v_begin;  // first parameter of each chunk
  std::vector<Tile> tiles;
};

class GlPingPong final : public Strategy {
 public:
  GlPingPong(gl::Platform platform, bool packed, int tile_option,
             const trim_texture::Options& trim_options)
      : packed_(packed) {
    try {
      context_ = gl::Context::create(platform);
    } catch (const gl::UnavailableError& e) {
      throw std::runtime_error(fmt::format("unavailable: {}", e.what()));
    }
    timer_ = std::make_unique<gl::DeviceTimer>(*context_);
    programs_ = std::make_unique<Programs>(*context_, packed_);
    tile_ = std::min(context_->max_texture_size(), context_->max_viewport());
    if (tile_option > 0) tile_ = std::min(tile_, tile_option);
    trims_ =
        std::make_unique<trim_texture::TrimTextures>(*context_, trim_options, std::string(name()));
  }

  ~GlPingPong() override {
    context_->make_current();
    for (const DeviceCopy& c : copies_) context_->gl().DeleteBuffers(1, &c.buffer);
    renderer_.reset();
    trims_.reset();
    surfaces_.clear();
    programs_.reset();
  }

  std::string_view name() const override { return packed_ ? "gl-pingpong-packed" : "gl-pingpong"; }
  Capabilities capabilities() const override {
    return gl_pingpong_descriptor(packed_).capabilities;
  }

  DeviceInfo device() const override {
    DeviceInfo d = context_->device_info();
    d.details["packed"] = std::to_string(packed_ ? 1 : 0);
    d.details["tile"] = std::to_string(tile_);
    d.details["tiles"] = std::to_string(tile_count_);
    // Counted from the draws the last evaluate() issued (gl::DrawCounts), 0 before one.
    d.details["passes"] = std::to_string(passes_);
    d.details["passes_basis"] = std::to_string(basis_passes_);
    d.details["bytes_uploaded"] = std::to_string(bytes_uploaded_);
    if (bytes_updated_) d.details["bytes_updated"] = std::to_string(bytes_updated_);
    trims_->add_details(d);
    return d;
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    samples_ = sample_parameters(scene, request.sampling);
    view_ = gl::orthographic_view(scene);
    context_->make_current();
    for (const DeviceCopy& c : copies_) context_->gl().DeleteBuffers(1, &c.buffer);
    copies_.clear();
    surfaces_.clear();
    bytes_uploaded_ = bytes_updated_ = 0;
    passes_ = basis_passes_ = 0;
    tile_count_ = 0;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
      surfaces_.push_back(upload_surface(scene.surfaces[i], samples_[i]));
    trims_->prepare(scene, samples_);
    context_->finish("gl-pingpong upload");
    context_->check("gl-pingpong upload");
  }

  // Only the control-point textures are written, in prepare()'s layout; a scene whose nets differ
  // in number, size or degree from the prepared one is an error, not a partial upload.
  void update_control_points(const Scene& scene) override {
    if (scene.surfaces.size() != surfaces_.size())
      throw std::invalid_argument(
          fmt::format("{}: update_control_points with {} surfaces, prepared with {}", name(),
                      scene.surfaces.size(), surfaces_.size()));
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const Surface& surface = scene.surfaces[i];
      const SurfaceOnGpu& s = surfaces_[i];
      if (surface.count_u != s.count_u || surface.count_v != s.count_v ||
          surface.degree_u != s.degree_u || surface.degree_v != s.degree_v)
        throw std::invalid_argument(fmt::format(
            "{}: update_control_points: surface '{}' is {}x{} of degree ({}, {}), prepared {}x{} "
            "of degree ({}, {})",
            name(), surface.name, surface.count_u, surface.count_v, surface.degree_u,
            surface.degree_v, s.count_u, s.count_v, s.degree_u, s.degree_v));
    }
    view_ = gl::orthographic_view(scene);  // as prepare() would frame the moved scene
    context_->make_current();
    bytes_updated_ = 0;
    for (std::size_t i = 0; i < surfaces_.size(); ++i)
      bytes_updated_ += upload_control(SurfaceNet<float>(scene.surfaces[i]), surfaces_[i].control);
    context_->finish("gl-pingpong control point update");
    context_->check("gl-pingpong control point update");
  }

  void evaluate() override {
    const gl::DrawCounts before = context_->draw_counts();
    basis_passes_ = 0;
    device_evaluate_s_ = timer_->time("gl-pingpong evaluate", [&] {
      for (SurfaceOnGpu& s : surfaces_) evaluate_surface(s);
    });
    passes_ = (context_->draw_counts() - before).passes;
  }

  DeviceTimes device_times() const override { return {device_evaluate_s_}; }

  bool classify() override { return trims_->classify(); }

  // 000 §4's rendering pass, as glsl-deboor draws (the shared grid renderer): each tile's result
  // texture holds sample (a, b) at texel (b, a). A grid tiled over several textures is drawn
  // tile by tile, so the cells between two tiles are not drawn (tiles exist only past
  // GL_MAX_TEXTURE_SIZE samples per side or with the test option "tile").
  bool render() override {
    context_->make_current();
    renderer().begin_frame();
    for (std::size_t i = 0; i < surfaces_.size(); ++i)
      for (const Tile& t : surfaces_[i].tiles) {
        const gl::Texture& result = t.sum[t.result];
        const int first_u = static_cast<int>(surfaces_[i].u_begin[static_cast<std::size_t>(t.cu)]);
        const int first_v = static_cast<int>(surfaces_[i].v_begin[static_cast<std::size_t>(t.cv)]);
        const auto trim = trims_->grid_trim(i, first_u, first_v);
        renderer().draw(gl::GridPoints{&result, result.height(), result.width(), 0, 0, false},
                        view_.data(), trim ? &*trim : nullptr);
      }
    renderer().end_frame("gl-pingpong render");
    context_->finish("gl-pingpong render");
    return true;
  }

  bool render_via_read_back() override {
    const EvalResult result = read_positions();
    context_->make_current();
    renderer().begin_frame();
    for (std::size_t i = 0; i < result.surfaces.size(); ++i) {
      const SurfaceSamples& samples = result.surfaces[i].samples;
      const auto trim = trims_->grid_trim(i);
      renderer().draw(result.surfaces[i].positions.f32(), static_cast<int>(samples.u.size()),
                      static_cast<int>(samples.v.size()), view_.data(), trim ? &*trim : nullptr);
    }
    renderer().end_frame("gl-pingpong render via read-back");
    context_->finish("gl-pingpong render via read-back");
    return true;
  }

  std::optional<RenderedImage> last_render() override {
    return gl::last_picture(*context_, renderer_.get());
  }

  EvalResult read_back() override {
    EvalResult out = read_positions();
    for (std::size_t i = 0; i < out.surfaces.size(); ++i)
      out.surfaces[i].inside = trims_->read_mask(i);
    return out;
  }

  // 000 §3.2: surface i evaluated at new samples from the next evaluate on; only what depends on
  // the samples is made again (parameters, first-span indices, basis and sum targets, and a
  // trimmed surface's sample table: its trim texture depends on the loops alone).
  void resample(std::size_t i, const SurfaceSamples& samples) {
    context_->make_current();
    samples_[i] = samples;
    tile_count_ -= surfaces_[i].tiles.size();
    make_grid(surfaces_[i], samples);
    trims_->resample(i, samples);
    context_->check("gl-pingpong resample");
  }

  // 000 §3.2's rendering: every surface evaluated, its output copied on the device into a vertex
  // buffer of its own (glReadPixels into a pixel-pack buffer: the output texture's row a is the
  // samples (a, 0..nv-1), so the buffer is in SurfaceSamples order), which is then drawn as the
  // array buffer into a width x height image, a trimmed surface's outside discarded by its trim
  // texture (000 §4, as render() does). Nothing is read back to the host. Grids must fit one tile
  // (the caller's limit). Returns the triangles drawn.
  std::uint64_t draw_from_device_copies(const std::array<float, 16>& mvp) {
    context_->make_current();
    const gl::Functions& gl = context_->gl();
    for (SurfaceOnGpu& s : surfaces_) evaluate_surface(s);
    copies_.resize(surfaces_.size());
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const Tile& t = surfaces_[i].tiles.front();
      const gl::Texture& result = t.sum[t.result];
      DeviceCopy& c = copies_[i];
      const GLsizeiptr bytes = GLsizeiptr{result.width()} * result.height() * 4 * sizeof(float);
      if (!c.buffer) gl.GenBuffers(1, &c.buffer);
      if (c.bytes != bytes) {
        gl.BindBuffer(GL_PIXEL_PACK_BUFFER, c.buffer);
        // Written and read by GL only.
        gl.BufferData(GL_PIXEL_PACK_BUFFER, bytes, nullptr, GL_STREAM_COPY);
        gl.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
        c.bytes = bytes;
      }
      result.bind_target();
      gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
      gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
      context_->copy_pixels_to_buffer(c.buffer, 0, 0, result.width(), result.height(), GL_RGBA,
                                      GL_FLOAT);
      c.nu = result.height();
      c.nv = result.width();
    }
    std::uint64_t triangles = 0;
    renderer().begin_frame();
    for (std::size_t i = 0; i < copies_.size(); ++i) {
      const DeviceCopy& c = copies_[i];
      const auto trim = trims_->grid_trim(i);
      triangles +=
          renderer().draw_device_points(c.buffer, c.nu, c.nv, mvp.data(), trim ? &*trim : nullptr);
    }
    renderer().end_frame("gl-pingpong LOD frame");
    context_->finish("gl-pingpong LOD frame");
    return triangles;
  }

  // Tests only: the vertex buffers as the last frame drew them, read back.
  std::vector<SurfaceResult> read_device_copies() {
    context_->make_current();
    std::vector<SurfaceResult> out(copies_.size());
    std::vector<float> texels;
    for (std::size_t i = 0; i < copies_.size(); ++i) {
      const DeviceCopy& c = copies_[i];
      texels.resize(static_cast<std::size_t>(c.bytes) / sizeof(float));
      context_->read_buffer(c.buffer, 0, c.bytes, texels.data());
      out[i].samples = samples_[i];
      out[i].positions = PointArray(Precision::f32, texels.size() / 4);
      float* xyz = out[i].positions.f32();
      for (std::size_t k = 0; k < texels.size() / 4; ++k)
        for (std::size_t d = 0; d < 3; ++d) xyz[k * 3 + d] = texels[k * 4 + d];
    }
    context_->check("gl-pingpong vertex buffer read-back");
    return out;
  }

  // The size of the image render() and draw_from_device_copies() draw; before the first draw.
  void set_render_size(int width, int height) {
    render_width_ = width;
    render_height_ = height;
  }
  int tile() const { return tile_; }
  gl::Context& context() { return *context_; }

 private:
  // The positions only: what the traditional render path (002 §4.1) reads back.
  EvalResult read_positions() {
    context_->make_current();
    const gl::Functions& gl = context_->gl();
    EvalResult out;
    out.surfaces.resize(surfaces_.size());
    std::vector<float> texels;
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const SurfaceSamples& samples = samples_[i];
      SurfaceResult& r = out.surfaces[i];
      r.samples = samples;
      r.positions = PointArray(Precision::f32, samples.count());
      float* xyz = r.positions.f32();
      const std::size_t nv = samples.v.size();
      for (const Tile& t : surfaces_[i].tiles) {
        const gl::Texture& result = t.sum[t.result];
        texels.resize(static_cast<std::size_t>(result.width()) * result.height() * 4);
        result.bind_target();
        gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
        gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
        context_->read_pixels(0, 0, result.width(), result.height(), GL_RGBA, GL_FLOAT,
                              texels.data());
        const std::size_t u0 = surfaces_[i].u_begin[static_cast<std::size_t>(t.cu)];
        const std::size_t v0 = surfaces_[i].v_begin[static_cast<std::size_t>(t.cv)];
        for (int a = 0; a < result.height(); ++a)
          for (int b = 0; b < result.width(); ++b) {
            const float* texel = &texels[(static_cast<std::size_t>(a) * result.width() + b) * 4];
            float* p = &xyz[((u0 + a) * nv + v0 + b) * 3];
            p[0] = texel[0];
            p[1] = texel[1];
            p[2] = texel[2];
          }
      }
    }
    context_->check("gl-pingpong read-back");
    return out;
  }

  // Created at the first draw: a run that never renders allocates no framebuffer.
  gl::GridRenderer& renderer() {
    if (!renderer_)
      renderer_ = std::make_unique<gl::GridRenderer>(*context_, render_width_, render_height_);
    return *renderer_;
  }

  // 000 §3.1's control-point texture: texel (j, i) = (w x, w y, w z, w) of P_ij.
  std::size_t upload_control(const SurfaceNet<float>& net, const gl::Texture& control) {
    return control.upload(GL_RGBA, GL_FLOAT, net.homogeneous.data(), sizeof(float) * 4);
  }

  SurfaceOnGpu upload_surface(const Surface& surface, const SurfaceSamples& samples) {
    // Grids larger than a texture are tiled; a control net larger than one is refused (it would
    // need the sub-mesh lookup split across textures, which the paper's layout does not have).
    if (std::max(surface.count_u, surface.count_v) > context_->max_texture_size())
      throw RefusedError(fmt::format(
          "surface '{}' has {}x{} control points; the control-point texture is limited to {} "
          "per side (GL_MAX_TEXTURE_SIZE)",
          surface.name, surface.count_u, surface.count_v, context_->max_texture_size()));
    const SurfaceNet<float> net(surface);
    SurfaceOnGpu s;
    s.degree_u = surface.degree_u;
    s.degree_v = surface.degree_v;
    s.count_u = surface.count_u;
    s.count_v = surface.count_v;
    s.control = gl::Texture(*context_, GL_RGBA32F, surface.count_v, surface.count_u, false);
    bytes_uploaded_ += upload_control(net, s.control);
    s.knots_u = net.knots_u;
    s.knots_v = net.knots_v;
    make_grid(s, samples);
    return s;
  }

  // The sample-dependent part of a surface on the device: parameter chunks and the tiles' targets.
  void make_grid(SurfaceOnGpu& s, const SurfaceSamples& samples) {
    s.u_begin.clear();
    s.v_begin.clear();
    s.tiles.clear();
    s.u_chunks = gl_pingpong::upload_chunks(*context_, samples.u, s.degree_u, s.count_u, s.knots_u,
                                            packed_, tile_, s.u_begin, bytes_uploaded_);
    s.v_chunks = gl_pingpong::upload_chunks(*context_, samples.v, s.degree_v, s.count_v, s.knots_v,
                                            packed_, tile_, s.v_begin, bytes_uploaded_);
    for (std::size_t cu = 0; cu < s.u_chunks.size(); ++cu)
      for (std::size_t cv = 0; cv < s.v_chunks.size(); ++cv) {
        Tile t;
        t.cu = static_cast<int>(cu);
        t.cv = static_cast<int>(cv);
        for (gl::Texture& sum : t.sum)
          sum = gl::Texture(*context_, GL_RGBA32F, s.v_chunks[cv].count(), s.u_chunks[cu].count(),
                            true);
        s.tiles.push_back(std::move(t));
      }
    tile_count_ += s.tiles.size();
  }

  void evaluate_surface(SurfaceOnGpu& s) {
    const gl::Functions& gl = context_->gl();
    // 000 §3.1 step 2: k-1 passes per direction (and per chunk of a tiled direction).
    const gl::DrawCounts before = context_->draw_counts();
    for (BasisChunk& c : s.u_chunks) c.raise(programs_->basis, s.degree_u);
    for (BasisChunk& c : s.v_chunks) c.raise(programs_->basis, s.degree_v);
    basis_passes_ += (context_->draw_counts() - before).passes;
    // Step 3: k_u x k_v accumulation passes per tile, then the divide.
    for (Tile& t : s.tiles) {
      const BasisChunk& u = s.u_chunks[static_cast<std::size_t>(t.cu)];
      const BasisChunk& v = s.v_chunks[static_cast<std::size_t>(t.cv)];
      t.sum[0].bind_target();  // tex1 starts at zero
      gl.ClearColor(0, 0, 0, 0);
      gl.Clear(GL_COLOR_BUFFER_BIT);
      gl.UseProgram(programs_->accumulate.id());
      s.control.bind_to_unit(1);
      u.result().bind_to_unit(2);
      v.result().bind_to_unit(3);
      u.first_index().bind_to_unit(4);
      v.first_index().bind_to_unit(5);
      int current = 0;
      for (int a = 0; a <= s.degree_u; ++a)
        for (int b = 0; b <= s.degree_v; ++b) {
          t.sum[1 - current].bind_target();
          t.sum[current].bind_to_unit(0);
          gl.Uniform1i(programs_->accumulate_a, a);
          gl.Uniform1i(programs_->accumulate_b, b);
          programs_->draw();
          current = 1 - current;
        }
      gl.UseProgram(programs_->divide.id());
      t.sum[1 - current].bind_target();
      t.sum[current].bind_to_unit(0);
      programs_->draw();
      t.result = 1 - current;
    }
  }

  bool packed_;
  std::unique_ptr<gl::Context> context_;
  std::unique_ptr<gl::DeviceTimer> timer_;
  std::unique_ptr<Programs> programs_;
  std::unique_ptr<trim_texture::TrimTextures> trims_;
  std::unique_ptr<gl::GridRenderer> renderer_;
  int render_width_ = kRenderSize, render_height_ = kRenderSize;
  // 000 §3.2: each surface's output copied on the device, drawn as a vertex buffer.
  struct DeviceCopy {
    GLuint buffer = 0;
    GLsizeiptr bytes = 0;
    int nu = 0, nv = 0;
  };
  std::vector<DeviceCopy> copies_;
  std::array<float, 16> view_{};
  int tile_ = 0;
  std::vector<SurfaceSamples> samples_;
  std::vector<SurfaceOnGpu> surfaces_;
  double device_evaluate_s_ = 0;
  std::size_t bytes_uploaded_ = 0, bytes_updated_ = 0, tile_count_ = 0;
  std::uint64_t passes_ = 0, basis_passes_ = 0;  // of the last evaluate()
};

// 000 §3.2 on the strategy itself: the same passes, targets and counted context as `run` times.
class PingPongLodRenderer final : public gl_pingpong::LodRenderer {
 public:
  PingPongLodRenderer(const Scene& scene, int width, int height, const StrategyOptions& options)
      : scene_(scene),
        strategy_(gl::platform_option(options), false, 0,
                  trim_texture::parse_options(options, "gl-pingpong")) {
    strategy_.set_render_size(width, height);
    EvalRequest request;
    request.sampling.grid_u = request.sampling.grid_v = 2;
    strategy_.prepare(scene, request);
    grids_.assign(scene.surfaces.size(), {2, 2});
  }

  DeviceInfo device() const override { return strategy_.device(); }

  void set_grid(std::size_t surface, int nu, int nv) override {
    if (grids_.at(surface) == std::pair{nu, nv}) return;
    if (nu < 2 || nv < 2 || std::max(nu, nv) > strategy_.tile())
      throw RefusedError(fmt::format(
          "surface {}: {}x{} samples; the LOD path draws one output texture per surface, 2 to {} "
          "samples per side",
          surface, nu, nv, strategy_.tile()));
    const Surface& s = scene_.surfaces[surface];
    SurfaceSamples samples;
    samples.u = grid_parameters(s.u_min(), s.u_max(), nu);
    samples.v = grid_parameters(s.v_min(), s.v_max(), nv);
    strategy_.resample(surface, samples);
    grids_[surface] = {nu, nv};
  }

  std::uint64_t draw_frame(const std::array<float, 16>& mvp) override {
    return strategy_.draw_from_device_copies(mvp);
  }

  gl_pingpong::LodCounts counts() const override {
    const gl::DrawCounts c = strategy_.context().draw_counts();
    return {c.draws, c.passes, c.host_read_backs, c.device_copies};
  }

  std::vector<SurfaceResult> read_vertex_buffers() override {
    return strategy_.read_device_copies();
  }

  RenderedImage picture() override {
    std::optional<RenderedImage> p = strategy_.last_render();
    if (!p) throw std::logic_error("gl-pingpong LOD: picture() before the first frame");
    return std::move(*p);
  }

 private:
  Scene scene_;
  mutable GlPingPong strategy_;
  std::vector<std::pair<int, int>> grids_;
};

StrategyEntry entry(bool packed_entry) {
  return make_entry(
      gl_pingpong_descriptor(packed_entry), gl::Context::probe_any,
      [packed_entry](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
        const auto it = options.extra.find("packed");
        const bool packed = packed_entry || (it != options.extra.end() && it->second == "1");
        const std::string_view strategy = packed ? "gl-pingpong-packed" : "gl-pingpong";
        return std::make_unique<GlPingPong>(gl::platform_option(options), packed,
                                            positive_option(options, "tile", strategy),
                                            trim_texture::parse_options(options, strategy));
      });
}

}  // namespace

std::unique_ptr<gl_pingpong::LodRenderer> gl_pingpong::make_lod_renderer(
    const Scene& scene, int width, int height, const StrategyOptions& options) {
  return std::make_unique<PingPongLodRenderer>(scene, width, height, options);
}

StrategyEntry gl_pingpong_entry() {
  return entry(false);
}
StrategyEntry gl_pingpong_packed_entry() {
  return entry(true);
}

}  // namespace nurbs
