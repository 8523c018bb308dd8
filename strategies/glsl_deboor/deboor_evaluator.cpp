#include "strategies/glsl_deboor/deboor_evaluator.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "reference/nurbs_math.h"
#include "strategies/glsl_deboor/de_boor.h"
#include "strategies/strategy.h"

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
extern const std::string_view glsl_deboor_de_boor_frag;
extern const std::string_view glsl_deboor_de_boor_source_h;
}  // namespace nurbs::embedded

namespace nurbs::glsl_deboor {

// The degree, then the single-source de Boor (GL 3.3 GLSL has no #include).
std::string de_boor_defines(int degree) {
  return fmt::format("#define DEGREE {}\n", degree) +
         std::string(embedded::glsl_deboor_de_boor_source_h);
}

namespace {

SurfaceSlot make_slot(std::size_t index, const Surface& s, const SurfaceSamples& samples) {
  SurfaceSlot slot;
  slot.surface = index;
  slot.degree_u = s.degree_u;
  slot.degree_v = s.degree_v;
  slot.count_u = s.count_u;
  slot.count_v = s.count_v;
  slot.knots_u.assign(s.knots_u.begin(), s.knots_u.end());
  slot.knots_v.assign(s.knots_v.begin(), s.knots_v.end());
  slot.runs_u = bin_into_spans(samples.u, s.degree_u, s.count_u, s.knots_u);
  slot.runs_v = bin_into_spans(samples.v, s.degree_v, s.count_v, s.knots_v);
  slot.nu = static_cast<int>(samples.u.size());
  slot.nv = static_cast<int>(samples.v.size());
  return slot;
}

// 002 §3.3.1 / Fig 2: texel (i, row0 + j) = (w x, w y, w z, w) of P_ij, for every slot of a page
// whose control texture is `control`; texels no slot covers are zero.
std::size_t upload_control(const Scene& scene, const std::vector<SurfaceSlot>& slots,
                           const gl::Texture& control) {
  const int width = control.width();
  std::vector<float> texels(static_cast<std::size_t>(width) * control.height() * 4, 0.0f);
  for (const SurfaceSlot& slot : slots) {
    const SurfaceNet<float> net(scene.surfaces[slot.surface]);
    for (int j = 0; j < slot.count_v; ++j)
      for (int i = 0; i < slot.count_u; ++i) {
        const Vec4<float>& p = net.at(i, j);
        std::copy(p.begin(), p.end(),
                  &texels[(static_cast<std::size_t>(slot.control_row0 + j) * width + i) * 4]);
      }
  }
  return control.upload(GL_RGBA, GL_FLOAT, texels.data(), sizeof(float) * 4);
}

gl::Texture parameter_texture(gl::Context& context, const std::vector<std::vector<double>>& rows,
                              std::size_t& bytes) {
  std::size_t width = 1;
  for (const auto& r : rows) width = std::max(width, r.size());
  std::vector<float> texels(width * rows.size(), 0.0f);
  for (std::size_t r = 0; r < rows.size(); ++r)
    std::transform(rows[r].begin(), rows[r].end(), texels.begin() + r * width,
                   [](double p) { return static_cast<float>(p); });
  gl::Texture t(context, GL_R32F, static_cast<int>(width), static_cast<int>(rows.size()), false);
  bytes += t.upload(GL_RED, GL_FLOAT, texels.data(), sizeof(float));
  return t;
}

}  // namespace

DeBoorProgram::DeBoorProgram(gl::Context& context, int degree)
    : program(context, embedded::gl_fullscreen_triangle_vert, embedded::glsl_deboor_de_boor_frag,
              de_boor_defines(degree), fmt::format("glsl-deboor de_boor.frag (degree {})", degree)),
      direction(program.uniform("direction")),
      span_first(program.uniform("span_first")),
      control_row0(program.uniform("control_row0")),
      output_row0(program.uniform("output_row0")),
      surface_row(program.uniform("surface_row")),
      knots(program.uniform("knots")) {
  const gl::Functions& gl = context.gl();
  gl.UseProgram(program.id());
  gl.Uniform1i(program.uniform("control"), 0);
  gl.Uniform1i(program.uniform("parameters"), 1);
  gl.UseProgram(0);
  context.check("glsl-deboor program");
}

Evaluator::Evaluator(gl::Context& context, int tile) : context_(context), tile_(tile) {
  context_.gl().GenVertexArrays(1, &vertex_array_);
}

const DeBoorProgram& Evaluator::program(int degree) {
  std::unique_ptr<DeBoorProgram>& p = programs_[degree];
  if (!p) p = std::make_unique<DeBoorProgram>(context_, degree);
  return *p;
}

Evaluator::~Evaluator() {
  context_.make_current();
  pages_.clear();
  context_.gl().DeleteVertexArrays(1, &vertex_array_);
}

std::size_t Evaluator::prepare(const Scene& scene, const std::vector<SurfaceSamples>& samples) {
  pages_.clear();
  // Pack surfaces into pages: rows stack until a texture side would exceed the tile.
  std::vector<std::vector<SurfaceSlot>> packed(1);
  int control_rows = 0, output_rows = 0;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    SurfaceSlot slot = make_slot(i, s, samples[i]);
    program(s.degree_u);
    program(s.degree_v);
    const int widest = std::max({slot.count_u, slot.count_v, slot.nu, slot.nv});
    if (widest > tile_)
      throw RefusedError(fmt::format(
          "surface '{}': {}x{} control points, {}x{} samples; glsl-deboor keeps one surface in "
          "one texture, limited to {} per side (GL_MAX_TEXTURE_SIZE / viewport / tile option)",
          s.name, s.count_u, s.count_v, slot.nu, slot.nv, tile_));
    if (control_rows + slot.count_v > tile_ || output_rows + slot.nv > tile_) {
      packed.emplace_back();
      control_rows = output_rows = 0;
    }
    slot.control_row0 = control_rows;
    slot.output_row0 = output_rows;
    slot.parameter_row = static_cast<int>(packed.back().size());
    control_rows += slot.count_v;
    output_rows += slot.nv;
    packed.back().push_back(std::move(slot));
  }
  std::size_t bytes = 0;
  for (std::vector<SurfaceSlot>& slots : packed) {
    int control_w = 1, control_h = 0, out_w = 1, out_h = 0;
    for (const SurfaceSlot& s : slots) {
      control_w = std::max(control_w, s.count_u);
      out_w = std::max(out_w, s.nu);
      control_h = s.control_row0 + s.count_v;
      out_h = s.output_row0 + s.nv;
    }
    std::vector<std::vector<double>> us, vs;
    for (const SurfaceSlot& slot : slots) {
      us.push_back(samples[slot.surface].u);
      vs.push_back(samples[slot.surface].v);
    }
    Page page;
    page.control = gl::Texture(context_, GL_RGBA32F, control_w, control_h, false);
    bytes += upload_control(scene, slots, page.control);
    page.curves = gl::Texture(context_, GL_RGBA32F, out_w, control_h, true);
    page.points = gl::Texture(context_, GL_RGBA32F, out_w, out_h, true);
    page.u_parameters = parameter_texture(context_, us, bytes);
    page.v_parameters = parameter_texture(context_, vs, bytes);
    page.slots = std::move(slots);
    pages_.push_back(std::move(page));
  }
  context_.check("glsl-deboor upload");
  return bytes;
}

std::size_t Evaluator::update_control_points(const Scene& scene) {
  std::size_t slots = 0;
  for (const Page& page : pages_) slots += page.slots.size();
  if (scene.surfaces.size() != slots)
    throw std::invalid_argument(
        fmt::format("glsl-deboor: update_control_points with {} surfaces, prepared with {}",
                    scene.surfaces.size(), slots));
  for (const Page& page : pages_)
    for (const SurfaceSlot& slot : page.slots) {
      const Surface& s = scene.surfaces[slot.surface];
      if (s.count_u != slot.count_u || s.count_v != slot.count_v || s.degree_u != slot.degree_u ||
          s.degree_v != slot.degree_v)
        throw std::invalid_argument(fmt::format(
            "glsl-deboor: update_control_points: surface '{}' is {}x{} of degree ({}, {}), "
            "prepared {}x{} of degree ({}, {})",
            s.name, s.count_u, s.count_v, s.degree_u, s.degree_v, slot.count_u, slot.count_v,
            slot.degree_u, slot.degree_v));
    }
  std::size_t bytes = 0;
  for (const Page& page : pages_) bytes += upload_control(scene, page.slots, page.control);
  context_.check("glsl-deboor control point update");
  return bytes;
}

void Evaluator::evaluate() {
  const gl::Functions& gl = context_.gl();
  gl.BindVertexArray(vertex_array_);
  float knots[2 * kMaxDegree];
  for (Page& page : pages_) {
    // Pass 1 (§3.3.2): each control row j of each surface as a curve in u; one quad per span
    // covering the span's u samples x the surface's count_v rows.
    page.curves.bind_target();
    page.control.bind_to_unit(0);
    page.u_parameters.bind_to_unit(1);
    for (const SurfaceSlot& s : page.slots) {
      const DeBoorProgram& p = *programs_.at(s.degree_u);
      gl.UseProgram(p.program.id());
      gl.Uniform1i(p.direction, 0);
      gl.Uniform1i(p.surface_row, s.parameter_row);
      gl.Uniform1i(p.control_row0, s.control_row0);
      gl.Uniform1i(p.output_row0, 0);
      for (const SpanRun& run : s.runs_u) {
        span_knots(s.degree_u, run.span, s.knots_u.data(), knots);
        gl.Uniform1fv(p.knots, 2 * s.degree_u, knots);
        gl.Uniform1i(p.span_first, run.span - s.degree_u);
        gl.Viewport(run.first, s.control_row0, run.count, s.count_v);
        context_.draw_arrays(GL_TRIANGLES, 0, 3);
      }
    }
    // Pass 2 (§3.3.3, Fig 6): the pass-1 texture as control points in v; quads across all u
    // samples x the span's v samples.
    page.points.bind_target();
    page.curves.bind_to_unit(0);
    page.v_parameters.bind_to_unit(1);
    for (const SurfaceSlot& s : page.slots) {
      const DeBoorProgram& p = *programs_.at(s.degree_v);
      gl.UseProgram(p.program.id());
      gl.Uniform1i(p.direction, 1);
      gl.Uniform1i(p.surface_row, s.parameter_row);
      gl.Uniform1i(p.control_row0, s.control_row0);
      gl.Uniform1i(p.output_row0, s.output_row0);
      for (const SpanRun& run : s.runs_v) {
        span_knots(s.degree_v, run.span, s.knots_v.data(), knots);
        gl.Uniform1fv(p.knots, 2 * s.degree_v, knots);
        gl.Uniform1i(p.span_first, run.span - s.degree_v);
        gl.Viewport(0, s.output_row0 + run.first, s.nu, run.count);
        context_.draw_arrays(GL_TRIANGLES, 0, 3);
      }
    }
  }
}

std::vector<std::vector<float>> Evaluator::read_back() {
  const gl::Functions& gl = context_.gl();
  std::size_t surfaces = 0;
  for (const Page& page : pages_) surfaces += page.slots.size();
  std::vector<std::vector<float>> out(surfaces);
  std::vector<float> texels;
  for (const Page& page : pages_) {
    const gl::Texture& t = page.points;
    texels.resize(static_cast<std::size_t>(t.width()) * t.height() * 4);
    t.bind_target();
    gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl.ReadPixels(0, 0, t.width(), t.height(), GL_RGBA, GL_FLOAT, texels.data());
    for (const SurfaceSlot& s : page.slots) {
      std::vector<float>& xyz = out[s.surface];
      xyz.resize(static_cast<std::size_t>(s.nu) * s.nv * 3);
      for (int a = 0; a < s.nu; ++a)
        for (int b = 0; b < s.nv; ++b) {
          const float* texel =
              &texels[(static_cast<std::size_t>(s.output_row0 + b) * t.width() + a) * 4];
          std::copy(texel, texel + 3, &xyz[(static_cast<std::size_t>(a) * s.nv + b) * 3]);
        }
    }
  }
  context_.check("glsl-deboor read-back");
  return out;
}

}  // namespace nurbs::glsl_deboor
