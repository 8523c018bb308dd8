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
#include "strategies/host_results.h"
#include "strategies/strategy_options.h"
#include "strategies/trim_texture/trim_texture.h"

namespace nurbs {
namespace {

using gl_pingpong::BasisAtlas;
using gl_pingpong::Programs;

// The image the render phases draw: glsl-deboor's size, so the two compare.
constexpr int kRenderSize = 512;
// Texels of a page of tile sums (unless one tile is larger). llvmpipe pays per pass for the size
// of the target drawn into, not only for the rectangle drawn: many-1024 at 64x64 evaluated in
// 2.2 s with pages of 64 x 256 texels, 3.4 s with 64 x 1024 and 4.3 s with 64 x 4096.
constexpr int kSumPageTexels = 64 * 256;

// Where a rectangle lies in a set of atlas pages: page, first texel.
struct AtlasPlace {
  int page = 0, x = 0, y = 0;
};

// Rectangles packed into pages of at most width x height texels, row by row (shelves as tall as
// their tallest rectangle); each page is as large as what it holds.
class ShelfPacker {
 public:
  ShelfPacker(int width, int height) : width_(width), height_(height) {}
  AtlasPlace place(int width, int height) {
    if (x_ + width > width_) {
      y_ += shelf_;
      x_ = shelf_ = 0;
    }
    if (pages_.empty() || y_ + height > height_) {
      pages_.push_back({0, 0});
      x_ = y_ = shelf_ = 0;
    }
    const AtlasPlace p{static_cast<int>(pages_.size()) - 1, x_, y_};
    x_ += width;
    shelf_ = std::max(shelf_, height);
    pages_.back() = {std::max(pages_.back().first, x_),
                     std::max(pages_.back().second, y_ + shelf_)};
    return p;
  }
  // Width and height of each page.
  const std::vector<std::pair<int, int>>& pages() const { return pages_; }

 private:
  int width_, height_, x_ = 0, y_ = 0, shelf_ = 0;
  std::vector<std::pair<int, int>> pages_;
};

// One tile of the evaluation grid: u-chunk cu x v-chunk cv, a width (v) x height (u) rectangle of
// a page of the sum atlas, whose running sum ping-pongs between the page's sum[0] and sum[1] (the
// paper's tex1/tex2); `result` is where the divide pass wrote the points.
struct Tile {
  int cu = 0, cv = 0;
  AtlasPlace place;
  int width = 0, height = 0;
  int result = 0;
};

// The render targets of the tiles of every surface: a tile is a rectangle of one page.
struct SumPage {
  gl::Texture sum[2];
};

struct SurfaceOnGpu {
  int degree_u = 0, degree_v = 0, count_u = 0, count_v = 0;
  AtlasPlace control;                   // count_v x count_u homogeneous control points (000 §3.1)
  std::vector<float> knots_u, knots_v;  // kept for a new grid (000 §3.2's LOD)
  std::vector<std::size_t> u_chunks, v_chunks;  // in the basis atlas
  std::vector<std::size_t> u_begin, v_begin;    // first parameter of each chunk
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
    results_ = gl::PixelBuffer(*context_, GL_STREAM_READ);
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
    sum_pages_.clear();
    control_pages_.clear();
    basis_ = BasisAtlas();
    results_ = gl::PixelBuffer();
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
    sum_pages_.clear();
    control_pages_.clear();
    basis_ = BasisAtlas();
    bytes_uploaded_ = bytes_updated_ = 0;
    passes_ = basis_passes_ = 0;
    tile_count_ = 0;
    times_.upload_s = timer_->time("gl-pingpong upload", [&] {
      place_control(scene);
      bytes_uploaded_ += upload_control(scene);
      make_grids();
      trims_->prepare(scene, samples_);
    });
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
    times_.upload_s = timer_->time("gl-pingpong control point update",
                                   [&] { bytes_updated_ = upload_control(scene); });
  }

  void evaluate() override {
    const gl::DrawCounts before = context_->draw_counts();
    basis_passes_ = 0;
    times_.evaluate_s = timer_->time("gl-pingpong evaluate", [&] { evaluate_surfaces(); });
    passes_ = (context_->draw_counts() - before).passes;
  }

  DeviceTimes device_times() const override { return times_; }

  bool classify() override { return trims_->classify(); }

  // 000 §4's rendering pass, as glsl-deboor draws (the shared grid renderer): each tile's result
  // rectangle holds sample (a, b) at texel (b, a) from its origin. A grid tiled over several
  // rectangles is drawn tile by tile, so the cells between two tiles are not drawn (tiles exist
  // only past GL_MAX_TEXTURE_SIZE samples per side or with the test option "tile").
  bool render() override {
    context_->make_current();
    renderer().begin_frame();
    for (std::size_t i = 0; i < surfaces_.size(); ++i)
      for (const Tile& t : surfaces_[i].tiles) {
        const int first_u = static_cast<int>(surfaces_[i].u_begin[static_cast<std::size_t>(t.cu)]);
        const int first_v = static_cast<int>(surfaces_[i].v_begin[static_cast<std::size_t>(t.cv)]);
        const auto trim = trims_->grid_trim(i, first_u, first_v);
        renderer().draw(
            gl::GridPoints{&result_of(t), t.height, t.width, t.place.x, t.place.y, false},
            view_.data(), trim ? &*trim : nullptr);
      }
    renderer().end_frame("gl-pingpong render");
    context_->finish("gl-pingpong render");
    return true;
  }

  bool render_via_read_back() override {
    EvalResult& result = render_points_;
    read_positions_into(result);
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
    EvalResult out;
    read_back_into(out);
    return out;
  }

  void read_back_into(EvalResult& out) override {
    read_positions_into(out);
    times_.read_back_s = last_copy_s_;
    for (std::size_t i = 0; i < out.surfaces.size(); ++i)
      out.surfaces[i].inside = trims_->read_mask(i);
  }

  // 000 §3.2: surface i evaluated at new samples from the next evaluate on; only what depends on
  // the samples is made again (parameters, first-span indices, basis and sum targets, and a
  // trimmed surface's sample table: its trim texture depends on the loops alone). The atlases hold
  // every surface's grid, so they are laid out again for all; the control points stay.
  void resample(std::size_t i, const SurfaceSamples& samples) {
    context_->make_current();
    samples_[i] = samples;
    make_grids();
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
    evaluate_surfaces();
    copies_.resize(surfaces_.size());
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const Tile& t = surfaces_[i].tiles.front();
      const gl::Texture& result = result_of(t);
      DeviceCopy& c = copies_[i];
      const GLsizeiptr bytes = GLsizeiptr{t.width} * t.height * 4 * sizeof(float);
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
      context_->copy_pixels_to_buffer(c.buffer, t.place.x, t.place.y, t.width, t.height, GL_RGBA,
                                      GL_FLOAT);
      c.nu = t.height;
      c.nv = t.width;
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
  // The positions only (what the traditional render path, 002 §4.1, reads back) into `out`,
  // reusing its storage. A tile's result rectangle holds sample (a, b) at texel (b, a): its rows
  // are runs of samples in SurfaceSamples order, so each tile is one glReadPixels of x y z (GL_RGB:
  // the driver drops w) into its place in one pixel-pack buffer (rows nv apart), every surface
  // back to back; the buffer is mapped once and copied into the results.
  void read_positions_into(EvalResult& out) {
    context_->make_current();
    std::size_t points = 0;
    for (const SurfaceSamples& s : samples_) points += s.count();
    const std::size_t bytes = points * 3 * sizeof(float);
    if (bytes == 0) {
      shape_results(out, samples_, Precision::f32, false);
      return;
    }
    const gl::Functions& gl = context_->gl();
    if (context_->software()) {
      // A software renderer's "device" memory is host memory and glReadPixels is itself the
      // host copy: each tile is read straight into its place in its surface's result, one pass
      // instead of a copy into the pixel-pack buffer and another out of it. A GPU reads through
      // the buffer: glReadPixels into pageable memory stalls the pipeline.
      shape_results(out, samples_, Precision::f32, false);
      last_copy_s_ = timer_->time("gl-pingpong read-back", [&] {
        gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
        for (std::size_t i = 0; i < surfaces_.size(); ++i) {
          const std::size_t nv = samples_[i].v.size();
          float* to = out.surfaces[i].positions.f32();
          gl.PixelStorei(GL_PACK_ROW_LENGTH, static_cast<GLint>(nv));
          for (const Tile& t : surfaces_[i].tiles) {
            const std::size_t u0 = surfaces_[i].u_begin[static_cast<std::size_t>(t.cu)];
            const std::size_t v0 = surfaces_[i].v_begin[static_cast<std::size_t>(t.cv)];
            result_of(t).bind_target();
            gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
            context_->read_pixels(t.place.x, t.place.y, t.width, t.height, GL_RGB, GL_FLOAT,
                                  to + (u0 * nv + v0) * 3);
          }
        }
        gl.PixelStorei(GL_PACK_ROW_LENGTH, 0);
      });
      context_->check("gl-pingpong read-back");
      return;
    }
    // Allocated by the first read-back, not prepare(): 201 MB cost llvmpipe ~120 ms, which
    // prepare() would add to every fresh strategy's upload.
    results_.reserve(bytes);
    last_copy_s_ = timer_->time("gl-pingpong read-back", [&] {
      std::size_t first = 0;  // the surface's first point in the buffer
      for (std::size_t i = 0; i < surfaces_.size();) {
        const std::size_t nv = samples_[i].v.size();
        if (const std::size_t end = whole_tile_run(i); end > i) {
          // Surfaces [i, end) are one tile each, stacked in one page as wide as their rows.
          const Tile& t = surfaces_[i].tiles.front();
          int rows = 0;
          for (std::size_t k = i; k < end; ++k) rows += surfaces_[k].tiles.front().height;
          result_of(t).bind_target();
          gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
          results_.read_pixels(first * 3 * sizeof(float), t.place.x, t.place.y, t.width, rows,
                               GL_RGB);
          for (; i < end; ++i) first += samples_[i].count();
          continue;
        }
        for (const Tile& t : surfaces_[i].tiles) {
          const std::size_t u0 = surfaces_[i].u_begin[static_cast<std::size_t>(t.cu)];
          const std::size_t v0 = surfaces_[i].v_begin[static_cast<std::size_t>(t.cv)];
          result_of(t).bind_target();
          gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
          results_.read_pixels((first + u0 * nv + v0) * 3 * sizeof(float), t.place.x, t.place.y,
                               t.width, t.height, GL_RGB, static_cast<GLint>(nv));
        }
        first += samples_[i].count();
        ++i;
      }
    });
    gl::PixelBuffer::Mapping mapped = results_.map_read(bytes, "gl-pingpong read-back");
    scatter_points(out, samples_, static_cast<const float*>(mapped.data()),
                   static_cast<const float*>(nullptr));
    mapped.release();
    context_->check("gl-pingpong read-back");
  }

  // Created at the first draw: a run that never renders allocates no framebuffer.
  gl::GridRenderer& renderer() {
    if (!renderer_)
      renderer_ = std::make_unique<gl::GridRenderer>(*context_, render_width_, render_height_);
    return *renderer_;
  }

  // The end of the run of surfaces from `i` whose grids are one tile each, filling the width of
  // one page and stacked there in order with the same result texture; `i` itself when surface i
  // is not such a surface.
  std::size_t whole_tile_run(std::size_t i) const {
    auto whole = [&](std::size_t k) {
      if (surfaces_[k].tiles.size() != 1) return false;
      const Tile& t = surfaces_[k].tiles.front();
      return t.place.x == 0 &&
             t.width == sum_pages_[static_cast<std::size_t>(t.place.page)].sum[0].width();
    };
    if (!whole(i)) return i;
    std::size_t end = i + 1;
    for (; end < surfaces_.size() && whole(end); ++end) {
      const Tile& previous = surfaces_[end - 1].tiles.front();
      const Tile& t = surfaces_[end].tiles.front();
      if (t.place.page != previous.place.page || t.result != previous.result ||
          t.place.y != previous.place.y + previous.height)
        break;
    }
    return end;
  }

  const gl::Texture& result_of(const Tile& t) const {
    return sum_pages_[static_cast<std::size_t>(t.place.page)].sum[t.result];
  }

  // 000 §3.1's control-point texture, one rectangle per surface in the pages of an atlas: texel
  // control + (j, i) = (w x, w y, w z, w) of P_ij. Laid out once per prepare(); surfaces_ starts
  // here.
  void place_control(const Scene& scene) {
    const int side = context_->max_texture_size();
    ShelfPacker packer(side, side);
    for (const Surface& surface : scene.surfaces) {
      // Grids larger than a texture are tiled; a control net larger than one is refused (it would
      // need the sub-mesh lookup split across textures, which the paper's layout does not have).
      if (std::max(surface.count_u, surface.count_v) > side)
        throw RefusedError(fmt::format(
            "surface '{}' has {}x{} control points; the control-point texture is limited to {} "
            "per side (GL_MAX_TEXTURE_SIZE)",
            surface.name, surface.count_u, surface.count_v, side));
      SurfaceOnGpu s;
      s.degree_u = surface.degree_u;
      s.degree_v = surface.degree_v;
      s.count_u = surface.count_u;
      s.count_v = surface.count_v;
      s.control = packer.place(surface.count_v, surface.count_u);
      const SurfaceNet<float> net(surface);
      s.knots_u = net.knots_u;
      s.knots_v = net.knots_v;
      surfaces_.push_back(std::move(s));
    }
    control_pages_.clear();
    for (const auto& [width, height] : packer.pages())
      control_pages_.emplace_back(*context_, GL_RGBA32F, width, height, false);
  }

  // Every surface's control points, one upload per atlas page (prepare() and every deforming
  // frame); returns the bytes sent.
  std::size_t upload_control(const Scene& scene) {
    std::vector<std::vector<float>> texels(control_pages_.size());
    for (std::size_t p = 0; p < control_pages_.size(); ++p)
      texels[p].assign(
          static_cast<std::size_t>(control_pages_[p].width()) * control_pages_[p].height() * 4,
          0.0f);
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const SurfaceOnGpu& s = surfaces_[i];
      const SurfaceNet<float> net(scene.surfaces[i]);
      std::vector<float>& page = texels[static_cast<std::size_t>(s.control.page)];
      const std::size_t width = static_cast<std::size_t>(
          control_pages_[static_cast<std::size_t>(s.control.page)].width());
      const std::size_t row = static_cast<std::size_t>(s.count_v) * 4;
      for (int i_u = 0; i_u < s.count_u; ++i_u)
        std::copy_n(&net.homogeneous[static_cast<std::size_t>(i_u) * s.count_v][0], row,
                    &page[((static_cast<std::size_t>(s.control.y + i_u)) * width +
                           static_cast<std::size_t>(s.control.x)) *
                          4]);
    }
    std::size_t bytes = 0;
    for (std::size_t p = 0; p < control_pages_.size(); ++p)
      bytes += control_pages_[p].upload(GL_RGBA, GL_FLOAT, texels[p].data(), sizeof(float) * 4);
    return bytes;
  }

  // The sample-dependent part of every surface on the device: parameter chunks of both directions
  // in one basis atlas, and the tiles' targets as rectangles of the sum atlas pages.
  void make_grids() {
    std::vector<gl_pingpong::ChunkInputs> chunks;
    const std::size_t step = static_cast<std::size_t>(tile_);
    auto cut = [&](const std::vector<double>& parameters, int degree, int count,
                   const std::vector<float>& knots, std::vector<std::size_t>& indices,
                   std::vector<std::size_t>& begins) {
      indices.clear();
      begins.clear();
      for (std::size_t begin = 0; begin < parameters.size(); begin += step) {
        const std::size_t end = std::min(parameters.size(), begin + step);
        indices.push_back(chunks.size());
        begins.push_back(begin);
        chunks.push_back(
            gl_pingpong::make_chunk_inputs(parameters, begin, end, degree, count, knots, packed_));
      }
    };
    // Sum pages one tile wide where the tiles are alike: tiles stack in surface order, so surfaces
    // whose grid is one tile lie back to back in SurfaceSamples order and a read-back takes a
    // page's run of them in one rectangle; a row is as long as a tile's, as in a texture of its
    // own. Pages stop at kSumPageTexels: a few textures for many small tiles, not one per tile.
    int widest = 1, tallest = 1;
    for (const SurfaceSamples& samples : samples_) {
      widest = std::max(widest, static_cast<int>(std::min(samples.v.size(), step)));
      tallest = std::max(tallest, static_cast<int>(std::min(samples.u.size(), step)));
    }
    ShelfPacker packer(widest, std::min(tile_, std::max(tallest, kSumPageTexels / widest)));
    tile_count_ = 0;
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      SurfaceOnGpu& s = surfaces_[i];
      cut(samples_[i].u, s.degree_u, s.count_u, s.knots_u, s.u_chunks, s.u_begin);
      cut(samples_[i].v, s.degree_v, s.count_v, s.knots_v, s.v_chunks, s.v_begin);
      s.tiles.clear();
      for (std::size_t cu = 0; cu < s.u_chunks.size(); ++cu)
        for (std::size_t cv = 0; cv < s.v_chunks.size(); ++cv) {
          Tile t;
          t.cu = static_cast<int>(cu);
          t.cv = static_cast<int>(cv);
          t.height = chunks[s.u_chunks[cu]].count;
          t.width = chunks[s.v_chunks[cv]].count;
          t.place = packer.place(t.width, t.height);
          s.tiles.push_back(t);
        }
      tile_count_ += s.tiles.size();
    }
    basis_ = BasisAtlas(*context_, chunks, packed_, tile_, bytes_uploaded_);
    sum_pages_.clear();
    for (const auto& [width, height] : packer.pages()) {
      SumPage page;
      for (gl::Texture& sum : page.sum)
        sum = gl::Texture(*context_, GL_RGBA32F, width, height, true);
      sum_pages_.push_back(std::move(page));
    }
  }

  // 000 §3.1 steps 2 and 3 for every surface, in surface order as the paper draws one surface.
  void evaluate_surfaces() {
    const gl::Functions& gl = context_->gl();
    // tex1 starts at zero: one clear of each page, whose tiles each read only their own rectangle.
    gl.ClearColor(0, 0, 0, 0);
    for (const SumPage& page : sum_pages_) {
      page.sum[0].bind_target();
      gl.Clear(GL_COLOR_BUFFER_BIT);
    }
    for (SurfaceOnGpu& s : surfaces_) evaluate_surface(s);
  }

  void evaluate_surface(SurfaceOnGpu& s) {
    const gl::Functions& gl = context_->gl();
    // 000 §3.1 step 2: k-1 passes per direction (and per chunk of a tiled direction).
    const gl::DrawCounts before = context_->draw_counts();
    for (std::size_t c : s.u_chunks) basis_.raise(programs_->basis, c, s.degree_u);
    for (std::size_t c : s.v_chunks) basis_.raise(programs_->basis, c, s.degree_v);
    basis_passes_ += (context_->draw_counts() - before).passes;
    // Step 3: k_u x k_v accumulation passes per tile, then the divide.
    const gl::Texture& control = control_pages_[static_cast<std::size_t>(s.control.page)];
    for (Tile& t : s.tiles) {
      const std::size_t u = s.u_chunks[static_cast<std::size_t>(t.cu)];
      const std::size_t v = s.v_chunks[static_cast<std::size_t>(t.cv)];
      const SumPage& page = sum_pages_[static_cast<std::size_t>(t.place.page)];
      gl.UseProgram(programs_->accumulate.id());
      control.bind_to_unit(1);
      basis_.result(u).bind_to_unit(2);
      basis_.result(v).bind_to_unit(3);
      basis_.first_index().bind_to_unit(4);
      basis_.first_index().bind_to_unit(5);
      gl.Uniform2i(programs_->origin, t.place.x, t.place.y);
      gl.Uniform2i(programs_->control_origin, s.control.x, s.control.y);
      const std::array<int, 4> place_u = basis_.place(u), place_v = basis_.place(v);
      gl.Uniform4i(programs_->place_u, place_u[0], place_u[1], place_u[2], place_u[3]);
      gl.Uniform4i(programs_->place_v, place_v[0], place_v[1], place_v[2], place_v[3]);
      int current = 0;
      for (int a = 0; a <= s.degree_u; ++a)
        for (int b = 0; b <= s.degree_v; ++b) {
          page.sum[1 - current].bind_target();
          gl.Viewport(t.place.x, t.place.y, t.width, t.height);
          page.sum[current].bind_to_unit(0);
          gl.Uniform1i(programs_->accumulate_a, a);
          gl.Uniform1i(programs_->accumulate_b, b);
          programs_->draw();
          current = 1 - current;
        }
      gl.UseProgram(programs_->divide.id());
      page.sum[1 - current].bind_target();
      gl.Viewport(t.place.x, t.place.y, t.width, t.height);
      page.sum[current].bind_to_unit(0);
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
  gl::PixelBuffer results_;   // read-backs land here; grown, never shrunk
  EvalResult render_points_;  // render_via_read_back's points, storage kept for the next
  std::array<float, 16> view_{};
  int tile_ = 0;
  std::vector<SurfaceSamples> samples_;
  std::vector<SurfaceOnGpu> surfaces_;
  // One upload per kind of data for all surfaces (many-4096 took a texture and its upload per
  // surface and per kind: ~100 us a surface on llvmpipe, ~500 on an H200's driver).
  std::vector<gl::Texture> control_pages_;
  BasisAtlas basis_;
  std::vector<SumPage> sum_pages_;
  double last_copy_s_ = 0;
  DeviceTimes times_;  // each phase's last device time (device_times())
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
