#include "strategies/glsl_deboor/deboor_evaluator.h"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "reference/nurbs_math.h"
#include "strategies/glsl_deboor/de_boor.h"
#include "strategies/host_results.h"
#include "strategies/strategy.h"

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
extern const std::string_view glsl_deboor_de_boor_frag;
extern const std::string_view glsl_deboor_de_boor_source_h;
extern const std::string_view glsl_deboor_span_quad_vert;
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

// Instances per row of the instance tables: rows stay within any texture width limit (2 * 256 and
// 2p * 256 <= 7680 texels) and a table still holds 256 instances per row of its height.
constexpr int kSpansPerRow = 256;

int degree_of(const SurfaceSlot& s, int direction) {
  return direction == 0 ? s.degree_u : s.degree_v;
}
const std::vector<SpanRun>& runs_of(const SurfaceSlot& s, int direction) {
  return direction == 0 ? s.runs_u : s.runs_v;
}

// What one span quad draws, in either draw mode: its rectangle in the pass's target (texels) and
// de_boor.frag's per-span values.
struct SpanQuad {
  int x = 0, y = 0, width = 0, height = 0;
  int span_first = 0, control_row0 = 0, output_row0 = 0, surface_row = 0;
  float knots[2 * kMaxDegree] = {};
};

// Pass 1 (§3.3.2): each control row of the surface as a curve in u, the span's u samples x the
// surface's count_v rows. Pass 2 (§3.3.3, Fig 6): the pass-1 texture as control points in v, the
// span's v samples x all u samples (the output is laid out v along x: see Page).
SpanQuad span_quad(const SurfaceSlot& s, const SpanRun& run, int direction) {
  SpanQuad q;
  const int degree = degree_of(s, direction);
  span_knots(degree, run.span, (direction == 0 ? s.knots_u : s.knots_v).data(), q.knots);
  q.span_first = run.span - degree;
  q.control_row0 = s.control_row0;
  q.output_row0 = direction == 0 ? 0 : s.output_row0;
  q.surface_row = s.parameter_row;
  if (direction == 0) {
    q.x = run.first;
    q.y = s.control_row0;
    q.width = run.count;
    q.height = s.count_v;
  } else {
    q.x = run.first;
    q.y = s.output_row0;
    q.width = run.count;
    q.height = s.nu;
  }
  return q;
}

// The instance tables of one pass and degree (layout: span_quad.vert, de_boor.frag).
SpanBatch make_batch(gl::Context& context, int degree, const std::vector<SpanQuad>& quads,
                     std::size_t& bytes) {
  SpanBatch b;
  b.degree = degree;
  b.count = static_cast<int>(quads.size());
  const int columns = std::min(b.count, kSpansPerRow);
  const int rows = (b.count + kSpansPerRow - 1) / kSpansPerRow;
  const int knots_per = 2 * degree;
  std::vector<float> spans(static_cast<std::size_t>(columns) * rows * 8, 0.0f),
      knots(static_cast<std::size_t>(columns) * rows * knots_per, 0.0f);
  for (std::size_t i = 0; i < quads.size(); ++i) {
    const SpanQuad& q = quads[i];
    const std::size_t row = i / kSpansPerRow, column = i % kSpansPerRow;
    const float values[8] = {float(q.x),           float(q.y),          float(q.width),
                             float(q.height),      float(q.span_first), float(q.control_row0),
                             float(q.output_row0), float(q.surface_row)};
    std::copy(values, values + 8, &spans[(row * columns + column) * 8]);
    std::copy(q.knots, q.knots + knots_per, &knots[(row * columns + column) * knots_per]);
  }
  b.spans = gl::Texture(context, GL_RGBA32F, 2 * columns, rows, false);
  bytes += b.spans.upload(GL_RGBA, GL_FLOAT, spans.data(), sizeof(float) * 4);
  b.knots = gl::Texture(context, GL_R32F, knots_per * columns, rows, false);
  bytes += b.knots.upload(GL_RED, GL_FLOAT, knots.data(), sizeof(float));
  return b;
}

// One batch per degree of the page's span quads in `direction`, in slot order.
std::vector<SpanBatch> make_batches(gl::Context& context, const std::vector<SurfaceSlot>& slots,
                                    int direction, std::size_t& bytes) {
  std::map<int, std::vector<SpanQuad>> by_degree;
  for (const SurfaceSlot& s : slots)
    for (const SpanRun& run : runs_of(s, direction))
      by_degree[degree_of(s, direction)].push_back(span_quad(s, run, direction));
  std::vector<SpanBatch> out;
  for (const auto& [degree, quads] : by_degree)
    out.push_back(make_batch(context, degree, quads, bytes));
  return out;
}

std::string program_defines(int degree, DrawMode draw) {
  return fmt::format("#define INSTANCED {}\n#define SPANS_PER_ROW {}\n",
                     draw == DrawMode::instanced ? 1 : 0, kSpansPerRow) +
         de_boor_defines(degree);
}

}  // namespace

DeBoorProgram::DeBoorProgram(gl::Context& context, int degree, DrawMode draw)
    : program(context,
              draw == DrawMode::instanced ? embedded::glsl_deboor_span_quad_vert
                                          : embedded::gl_fullscreen_triangle_vert,
              embedded::glsl_deboor_de_boor_frag, program_defines(degree, draw),
              fmt::format("glsl-deboor de_boor.frag (degree {}, {})", degree,
                          draw == DrawMode::instanced ? "instanced" : "per-span")),
      direction(program.uniform("direction")) {
  const gl::Functions& gl = context.gl();
  gl.UseProgram(program.id());
  gl.Uniform1i(program.uniform("control"), 0);
  gl.Uniform1i(program.uniform("parameters"), 1);
  if (draw == DrawMode::instanced) {
    gl.Uniform1i(program.uniform("spans"), 2);
    gl.Uniform1i(program.uniform("span_knots"), 3);
    target_size = program.uniform("target_size");
  } else {
    span_first = program.uniform("span_first");
    control_row0 = program.uniform("control_row0");
    output_row0 = program.uniform("output_row0");
    surface_row = program.uniform("surface_row");
    knots = program.uniform("knots");
  }
  gl.UseProgram(0);
  context.check("glsl-deboor program");
}

Evaluator::Evaluator(gl::Context& context, int tile, DrawMode draw)
    : context_(context),
      tile_(tile),
      draw_(draw),
      results_(context, GL_STREAM_READ),
      timer_(context) {
  context_.gl().GenVertexArrays(1, &vertex_array_);
}

const DeBoorProgram& Evaluator::program(int degree) {
  std::unique_ptr<DeBoorProgram>& p = programs_[degree];
  if (!p) p = std::make_unique<DeBoorProgram>(context_, degree, draw_);
  return *p;
}

Evaluator::~Evaluator() {
  context_.make_current();
  pages_.clear();
  results_ = gl::PixelBuffer();
  context_.gl().DeleteVertexArrays(1, &vertex_array_);
}

std::size_t Evaluator::prepare(const Scene& scene, const std::vector<SurfaceSamples>& samples) {
  pages_.clear();
  samples_ = samples;
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
    if (control_rows + slot.count_v > tile_ || output_rows + slot.nu > tile_) {
      packed.emplace_back();
      control_rows = output_rows = 0;
    }
    slot.control_row0 = control_rows;
    slot.output_row0 = output_rows;
    slot.parameter_row = static_cast<int>(packed.back().size());
    control_rows += slot.count_v;
    output_rows += slot.nu;
    packed.back().push_back(std::move(slot));
  }
  std::size_t bytes = 0;
  for (std::vector<SurfaceSlot>& slots : packed) {
    int control_w = 1, control_h = 0, curve_w = 1, out_w = 1, out_h = 0;
    for (const SurfaceSlot& s : slots) {
      control_w = std::max(control_w, s.count_u);
      out_w = std::max(out_w, s.nv);
      curve_w = std::max(curve_w, s.nu);
      control_h = s.control_row0 + s.count_v;
      out_h = s.output_row0 + s.nu;
    }
    std::vector<std::vector<double>> us, vs;
    for (const SurfaceSlot& slot : slots) {
      us.push_back(samples[slot.surface].u);
      vs.push_back(samples[slot.surface].v);
    }
    Page page;
    page.control = gl::Texture(context_, GL_RGBA32F, control_w, control_h, false);
    bytes += upload_control(scene, slots, page.control);
    page.curves = gl::Texture(context_, GL_RGBA32F, curve_w, control_h, true);
    page.points = gl::Texture(context_, GL_RGBA32F, out_w, out_h, true);
    page.u_parameters = parameter_texture(context_, us, bytes);
    page.v_parameters = parameter_texture(context_, vs, bytes);
    if (draw_ == DrawMode::instanced) {
      page.batches_u = make_batches(context_, slots, 0, bytes);
      page.batches_v = make_batches(context_, slots, 1, bytes);
    }
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

std::size_t Evaluator::evaluate() {
  context_.gl().BindVertexArray(vertex_array_);
  std::size_t quads = 0;
  for (const Page& page : pages_) {
    // Pass 1 into the curve texture from the control points, pass 2 into the output from it.
    for (int direction : {0, 1}) {
      (direction == 0 ? page.curves : page.points).bind_target();
      (direction == 0 ? page.control : page.curves).bind_to_unit(0);
      (direction == 0 ? page.u_parameters : page.v_parameters).bind_to_unit(1);
      quads += draw_ == DrawMode::instanced ? draw_instanced(page, direction)
                                            : draw_per_span(page, direction);
    }
  }
  return quads;
}

std::size_t Evaluator::draw_per_span(const Page& page, int direction) {
  const gl::Functions& gl = context_.gl();
  std::size_t quads = 0;
  for (const SurfaceSlot& s : page.slots) {
    const DeBoorProgram& p = *programs_.at(degree_of(s, direction));
    gl.UseProgram(p.program.id());
    gl.Uniform1i(p.direction, direction);
    for (const SpanRun& run : runs_of(s, direction)) {
      const SpanQuad q = span_quad(s, run, direction);
      gl.Uniform1i(p.surface_row, q.surface_row);
      gl.Uniform1i(p.control_row0, q.control_row0);
      gl.Uniform1i(p.output_row0, q.output_row0);
      gl.Uniform1fv(p.knots, 2 * degree_of(s, direction), q.knots);
      gl.Uniform1i(p.span_first, q.span_first);
      gl.Viewport(q.x, q.y, q.width, q.height);
      context_.draw_arrays(GL_TRIANGLES, 0, 3);
      ++quads;
    }
  }
  return quads;
}

std::size_t Evaluator::draw_instanced(const Page& page, int direction) {
  const gl::Functions& gl = context_.gl();
  std::size_t quads = 0;
  const gl::Texture& target = direction == 0 ? page.curves : page.points;
  for (const SpanBatch& b : direction == 0 ? page.batches_u : page.batches_v) {
    const DeBoorProgram& p = *programs_.at(b.degree);
    gl.UseProgram(p.program.id());
    gl.Uniform1i(p.direction, direction);
    gl.Uniform2i(p.target_size, target.width(), target.height());
    b.spans.bind_to_unit(2);
    b.knots.bind_to_unit(3);
    context_.draw_arrays_instanced(GL_TRIANGLES, 0, 6, b.count);
    quads += static_cast<std::size_t>(b.count);
  }
  return quads;
}

void Evaluator::read_back_into(EvalResult& out) {
  std::size_t points = 0;
  std::vector<std::size_t> first(samples_.size());  // each surface's first point in the buffer
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    first[i] = points;
    points += samples_[i].count();
  }
  const std::size_t bytes = points * 3 * sizeof(float);
  if (bytes == 0) {
    shape_results(out, samples_, Precision::f32, false);
    return;
  }
  const gl::Functions& gl = context_.gl();
  if (context_.software()) {
    // A software renderer's "device" memory is host memory and glReadPixels is itself the host
    // copy: each surface is read straight into its result, one pass over the bytes instead of a
    // copy into the pixel-pack buffer and another out of it (llvmpipe at patch144 4096²: 0.24-0.35
    // of the GL link row through the buffer). A GPU reads through the buffer: glReadPixels into
    // pageable memory stalls the pipeline (0.2 GB/s on an H200).
    shape_results(out, samples_, Precision::f32, false);
    read_back_device_s_ = timer_.time("glsl-deboor read-back", [&] {
      gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
      for (const Page& page : pages_) {
        page.points.bind_target();
        gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
        for (const SurfaceSlot& s : page.slots)
          if (s.nv > 0 && s.nu > 0)
            context_.read_pixels(0, s.output_row0, s.nv, s.nu, GL_RGB, GL_FLOAT,
                                 out.surfaces[s.surface].positions.f32());
      }
    });
    context_.check("glsl-deboor read-back");
    return;
  }
  results_.reserve(bytes);
  read_back_device_s_ = timer_.time("glsl-deboor read-back", [&] {
    for (const Page& page : pages_) {
      page.points.bind_target();
      gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
      // Slots follow each other in rows and in scene order: a run of slots as wide as the page is
      // one rectangle of whole rows, already in the buffer's order; a narrower slot is its own.
      const int width = page.points.width();
      for (std::size_t k = 0; k < page.slots.size();) {
        const SurfaceSlot& s = page.slots[k];
        std::size_t end = k + 1;
        int rows = s.nu;
        if (s.nv == width)
          for (; end < page.slots.size() && page.slots[end].nv == width; ++end)
            rows += page.slots[end].nu;
        if (s.nv > 0 && rows > 0)
          results_.read_pixels(first[s.surface] * 3 * sizeof(float), 0, s.output_row0, s.nv, rows,
                               GL_RGB);
        k = end;
      }
    }
  });
  gl::PixelBuffer::Mapping mapped = results_.map_read(bytes, "glsl-deboor read-back");
  scatter_points(out, samples_, static_cast<const float*>(mapped.data()),
                 static_cast<const float*>(nullptr));
  mapped.release();
  context_.check("glsl-deboor read-back");
}

std::vector<std::vector<float>> Evaluator::read_back() {
  EvalResult result;
  read_back_into(result);
  std::vector<std::vector<float>> out(result.surfaces.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const PointArray& p = result.surfaces[i].positions;
    out[i].assign(p.f32(), p.f32() + 3 * p.size());
  }
  return out;
}

}  // namespace nurbs::glsl_deboor
