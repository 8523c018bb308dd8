#include "strategies/trim_texture/trim_texture.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "reference/trim_classify.h"

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
extern const std::string_view trim_texture_trim_fan_vert;
extern const std::string_view trim_texture_trim_fan_frag;
extern const std::string_view trim_texture_trim_lookup_frag;
}  // namespace nurbs::embedded

namespace nurbs::trim_texture {

struct TrimTextures::Surface {
  gl::Texture trim;        // R x R, R8, u along x, v along y
  gl::Texture parameters;  // max(nu, nv) x 2, RG32F: texel index, trim-texture coordinate
  gl::Texture mask;        // nv x nu, R8: texel (b, a) is sample a * nv + b
  int nu = 0, nv = 0;
  double u_min = 0, u_max = 0, v_min = 0, v_max = 0;  // the domain the texture spans
  std::string name;
};

TrimTextures::TrimTextures(gl::Context& context, const Options& options, std::string strategy)
    : context_(context), options_(options), strategy_(std::move(strategy)) {
  if (options_.resolution > context_.max_texture_size() ||
      options_.resolution > context_.max_viewport())
    throw RefusedError(fmt::format("{}: trim-resolution {} exceeds this device's texture limit {}",
                                   strategy_, options_.resolution,
                                   std::min(context_.max_texture_size(), context_.max_viewport())));
  const gl::Functions& gl = context_.gl();
  fan_ = std::make_unique<gl::Program>(context_, embedded::trim_texture_trim_fan_vert,
                                       embedded::trim_texture_trim_fan_frag, "",
                                       "trim_texture trim_fan");
  lookup_ = std::make_unique<gl::Program>(context_, embedded::gl_fullscreen_triangle_vert,
                                          embedded::trim_texture_trim_lookup_frag, "",
                                          "trim_texture trim_lookup");
  gl.UseProgram(lookup_->id());
  gl.Uniform1i(lookup_->uniform("trim"), 0);
  gl.Uniform1i(lookup_->uniform("parameters"), 1);
  gl.UseProgram(0);
  gl.GetIntegerv(GL_SUBPIXEL_BITS, &subpixel_bits_);
  gl.GenVertexArrays(1, &vertex_array_);
  gl.GenBuffers(1, &vertex_buffer_);
  context_.check(fmt::format("{} trim texture programs", strategy_));
}

TrimTextures::~TrimTextures() {
  context_.make_current();
  surfaces_.clear();
  context_.gl().DeleteBuffers(1, &vertex_buffer_);
  context_.gl().DeleteVertexArrays(1, &vertex_array_);
}

void TrimTextures::draw_trim(const std::vector<std::vector<Point2>>& polygons,
                             const nurbs::Surface& surface, const gl::Texture& target) {
  const gl::Functions& gl = context_.gl();
  const double u0 = surface.u_min(), du = surface.u_max() - u0;
  const double v0 = surface.v_min(), dv = surface.v_max() - v0;
  // Clip space from (u, v) in double, so the polygon is placed to float precision of the texture,
  // not of the parameters. Texel (i, j) then covers [u0 + i du/R, u0 + (i+1) du/R] (and likewise
  // in v) and rasterization decides it at its centre: the paper does not say where a texel
  // samples the domain; pixel centres are what GL gives.
  std::vector<float> vertices;
  std::vector<std::pair<GLint, GLsizei>> fans;
  for (const std::vector<Point2>& polygon : polygons) {
    if (polygon.size() < 3) continue;  // no area: no texel changes parity
    fans.emplace_back(static_cast<GLint>(vertices.size() / 2),
                      static_cast<GLsizei>(polygon.size()));
    for (const Point2& p : polygon) {
      vertices.push_back(static_cast<float>(2 * (p[0] - u0) / du - 1));
      vertices.push_back(static_cast<float>(2 * (p[1] - v0) / dv - 1));
    }
  }
  target.bind_target();
  gl.ClearColor(0, 0, 0, 0);
  gl.Clear(GL_COLOR_BUFFER_BIT);
  gl.UseProgram(fan_->id());
  gl.BindVertexArray(vertex_array_);
  gl.BindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  gl.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
                vertices.data(), GL_STREAM_DRAW);
  gl.EnableVertexAttribArray(0);
  gl.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  // 000 §4: "triangles connecting a common origin to each polygon edge in turn are rasterized,
  // but only those regions that are filled an odd number of times are finally rendered ... we
  // use an alternate implementation based on the alpha blending functionality" (after Woo et al.).
  // The common origin is the polygon's first vertex (GL_TRIANGLE_FAN): triangles sharing an edge
  // never both cover a texel centre (GL's rasterization rules), so each texel counts the fan
  // triangles over its centre exactly. Blending ONE_MINUS_DST_COLOR, ZERO with a source of 1
  // makes each triangle toggle the texel (dst' = 1 - dst): the odd/even count by blending, as the
  // paper asks, with no stencil buffer and no logic op (an XOR logic op would do the same; the
  // paper names blending). Loops need no orientation and holes need no special case: toggles of
  // separate loops compose.
  gl.Enable(GL_BLEND);
  gl.BlendFunc(GL_ONE_MINUS_DST_COLOR, GL_ZERO);
  for (const auto& [first, count] : fans) context_.draw_arrays(GL_TRIANGLE_FAN, first, count);
  gl.Disable(GL_BLEND);
  gl.BindVertexArray(0);
}

// The sample table: per u (row 0) and v (row 1) sample its texel, floor((u - u0) / du * R)
// clamped to [0, R-1] (the texel whose centre is nearest), and its trim-texture coordinate for the
// renderer's interpolated lookup; and the mask the lookup pass writes, one texel per sample.
void TrimTextures::make_sample_table(Surface& s, const SurfaceSamples& grid) {
  const int limit = std::min(context_.max_texture_size(), context_.max_viewport());
  const int r = options_.resolution;
  s.nu = static_cast<int>(grid.u.size());
  s.nv = static_cast<int>(grid.v.size());
  if (std::max(s.nu, s.nv) > limit)
    throw RefusedError(fmt::format(
        "{}: surface '{}' is sampled {}x{}; the trim mask is one texture, limited to {} per side",
        strategy_, s.name, s.nu, s.nv, limit));
  const int width = std::max(s.nu, s.nv);
  std::vector<float> table(static_cast<std::size_t>(width) * 2 * 4, 0.0f);
  auto fill = [&](const std::vector<double>& values, double lo, double hi, int row) {
    for (std::size_t k = 0; k < values.size(); ++k) {
      const double t = (values[k] - lo) / (hi - lo);
      const int texel = std::clamp(static_cast<int>(std::floor(t * r)), 0, r - 1);
      float* texel_out = &table[(static_cast<std::size_t>(row) * width + k) * 4];
      texel_out[0] = static_cast<float>(texel) + 0.5f;  // exact; int() in the shader floors
      texel_out[1] = static_cast<float>(t);
    }
  };
  fill(grid.u, s.u_min, s.u_max, 0);
  fill(grid.v, s.v_min, s.v_max, 1);
  s.parameters = gl::Texture(context_, GL_RG32F, width, 2, false);
  s.parameters.upload(GL_RGBA, GL_FLOAT, table.data(), sizeof(float) * 4);
  s.mask = gl::Texture(context_, GL_R8, s.nv, s.nu, true);
}

void TrimTextures::resample(std::size_t surface, const SurfaceSamples& grid) {
  if (surface >= surfaces_.size() || !surfaces_[surface]) return;
  context_.make_current();
  make_sample_table(*surfaces_[surface], grid);
  classified_ = false;
  context_.check(fmt::format("{} trim sample table", strategy_));
}

void TrimTextures::prepare(const Scene& scene, const std::vector<SurfaceSamples>& samples) {
  surfaces_.clear();
  polygon_vertices_ = 0;
  classified_ = false;
  const int r = options_.resolution;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const nurbs::Surface& surface = scene.surfaces[i];
    if (!surface.trim) {
      surfaces_.push_back(nullptr);
      continue;
    }
    auto s = std::make_unique<Surface>();
    s->u_min = surface.u_min();
    s->u_max = surface.u_max();
    s->v_min = surface.v_min();
    s->v_max = surface.v_max();
    s->name = surface.name;
    make_sample_table(*s, samples[i]);
    const std::vector<std::vector<Point2>> polygons =
        trim_polygons(*surface.trim, options_.tolerance * domain_diagonal(surface));
    for (const auto& p : polygons) polygon_vertices_ += p.size();
    s->trim = gl::Texture(context_, GL_R8, r, r, true);
    draw_trim(polygons, surface, s->trim);
    surfaces_.push_back(std::move(s));
  }
  context_.bind_framebuffer(0);
  context_.finish(fmt::format("{} trim textures", strategy_));
  context_.check(fmt::format("{} trim textures", strategy_));
}

bool TrimTextures::classify() {
  context_.make_current();
  const gl::Functions& gl = context_.gl();
  gl.UseProgram(lookup_->id());
  gl.BindVertexArray(vertex_array_);
  gl.DisableVertexAttribArray(0);
  for (const auto& s : surfaces_) {
    if (!s) continue;
    s->mask.bind_target();
    s->trim.bind_to_unit(0);
    s->parameters.bind_to_unit(1);
    context_.draw_arrays(GL_TRIANGLES, 0, 3);
  }
  gl.BindVertexArray(0);
  context_.finish(fmt::format("{} classify", strategy_));
  context_.check(fmt::format("{} classify", strategy_));
  classified_ = true;
  return true;
}

std::vector<std::uint8_t> TrimTextures::read_mask(std::size_t surface) {
  const auto& s = surfaces_.at(surface);
  if (!s || !classified_) return {};
  const gl::Functions& gl = context_.gl();
  std::vector<std::uint8_t> mask(static_cast<std::size_t>(s->nu) * s->nv);
  s->mask.bind_target();
  gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  context_.read_pixels(0, 0, s->nv, s->nu, GL_RED, GL_UNSIGNED_BYTE, mask.data());
  context_.check(fmt::format("{} trim mask read-back", strategy_));
  for (std::uint8_t& m : mask) m = m >= 128 ? 1 : 0;
  return mask;
}

std::optional<gl::GridTrim> TrimTextures::grid_trim(std::size_t surface, int first_u,
                                                    int first_v) const {
  if (surface >= surfaces_.size() || !surfaces_[surface]) return std::nullopt;
  const Surface& s = *surfaces_[surface];
  return gl::GridTrim{&s.trim, &s.parameters, first_u, first_v};
}

void TrimTextures::add_details(DeviceInfo& device) const {
  device.details["trim_resolution"] = std::to_string(options_.resolution);
  device.details["trim_tolerance"] = fmt::format("{}", options_.tolerance);
  device.details["trim_tolerance_unit"] = "fraction of the (u,v) domain diagonal";
  device.details["trim_polygon_vertices"] = std::to_string(polygon_vertices_);
  device.details["trim_subpixel_bits"] = std::to_string(subpixel_bits_);
}

}  // namespace nurbs::trim_texture
