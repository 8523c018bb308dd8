// The GL side of glsl-deboor (002 §3.3): atlas pages, the two de Boor passes, read-back. Kept
// apart from the Strategy wrapper so that the no-read-back renderer and the wavelet LOD can use
// the evaluated textures where they lie.
#pragma once

#include <map>
#include <memory>
#include <vector>

#include "reference/sampling.h"
#include "reference/surface.h"
#include "strategies/gl_context/gl_program.h"
#include "strategies/glsl_deboor/span_runs.h"
#include "strategies/strategy.h"

namespace nurbs::glsl_deboor {

// One surface's place in its page.
struct SurfaceSlot {
  std::size_t surface = 0;  // index in the scene
  int degree_u = 0, degree_v = 0, count_u = 0, count_v = 0;
  std::vector<float> knots_u, knots_v;
  std::vector<SpanRun> runs_u, runs_v;
  int nu = 0, nv = 0;     // samples per direction
  int control_row0 = 0;   // rows [control_row0, + count_v) of the control and curve atlases
  int output_row0 = 0;    // rows [output_row0, + nu) of the output atlas
  int parameter_row = 0;  // row of the parameter textures
};

// How a pass draws its span quads. per_span: one draw each, its viewport and uniforms set
// before it (002 §3.3.2's form). instanced: one instanced draw per pass and degree, the per-span
// values in instance tables (span_quad.vert); the same texels bit for bit, far fewer draws.
enum class DrawMode { per_span, instanced };

// The span quads of one pass and degree in a page, for DrawMode::instanced (layout:
// span_quad.vert and de_boor.frag).
struct SpanBatch {
  int degree = 0;
  int count = 0;      // instances
  gl::Texture spans;  // RGBA32F: rectangle, then (span - p, control_row0, output_row0, surface_row)
  gl::Texture knots;  // R32F: the 2p knots of each
};

// Surfaces sharing one set of textures. Output texel (b, output_row0 + a) = S(u_a, v_b), w = 1:
// a row of the output is a run of samples in SurfaceSamples order (a * nv + b), so a read-back
// takes whole rows as they lie and its host side is one copy (Evaluator::read_back_into).
struct Page {
  std::vector<SurfaceSlot> slots;
  gl::Texture control;                          // count_u x count_v per surface, homogeneous
  gl::Texture curves;                           // nu x count_v per surface: pass 1
  gl::Texture points;                           // nv x nu per surface: pass 2
  gl::Texture u_parameters, v_parameters;       // R32F, one row per surface
  std::vector<SpanBatch> batches_u, batches_v;  // DrawMode::instanced: pass 1, pass 2
};

// What goes after a de Boor shader's #version line: DEGREE and the single-source de Boor
// (de_boor_source.h). The test that runs that source as GLSL builds its programs with it too.
std::string de_boor_defines(int degree);

// de_boor.frag compiled for one degree and draw mode, with its uniform locations (those of the
// other mode: -1).
struct DeBoorProgram {
  DeBoorProgram(gl::Context& context, int degree, DrawMode draw);
  gl::Program program;
  GLint direction, span_first = -1, control_row0 = -1, output_row0 = -1, surface_row = -1,
                   knots = -1, target_size = -1;
};

class Evaluator {
 public:
  // `tile`: largest texture side / viewport to use.
  Evaluator(gl::Context& context, int tile, DrawMode draw = DrawMode::per_span);
  ~Evaluator();

  // Builds the pages and uploads control points, parameters; throws RefusedError when one
  // surface does not fit a texture. Returns the bytes uploaded.
  std::size_t prepare(const Scene& scene, const std::vector<SurfaceSamples>& samples);
  // Rewrites only the pages' control textures from `scene`'s moved points (000 §5, deforming
  // surfaces): knots, spans, parameters and targets stay. Throws std::invalid_argument when a net
  // differs in number, size or degree from the prepared scene's. Returns the bytes uploaded.
  std::size_t update_control_points(const Scene& scene);
  // Both passes over every page (no synchronisation). Returns the span quads drawn: one per draw
  // per span, one per instance instanced.
  std::size_t evaluate();
  // Positions, (x, y, z) per sample, in each surface's sample order (a * nv + b).
  std::vector<std::vector<float>> read_back();
  // The positions into `out` (Strategy::read_back_into, reusing its storage): every surface's
  // rows read as x y z (GL_RGB) into one pixel-pack buffer, back to back in scene order, which is
  // mapped once and copied into the results. Trim masks are left empty.
  void read_back_into(EvalResult& out);
  // GL_TIME_ELAPSED of the last read_back_into's copies into the pixel-pack buffer.
  double read_back_device_s() const { return read_back_device_s_; }

  const std::vector<Page>& pages() const { return pages_; }

 private:
  std::size_t draw_per_span(const Page& page, int direction);
  std::size_t draw_instanced(const Page& page, int direction);

  gl::Context& context_;
  int tile_;
  DrawMode draw_;
  // Compiled in prepare() for the degrees a scene has, kept for later scenes.
  const DeBoorProgram& program(int degree);
  std::map<int, std::unique_ptr<DeBoorProgram>> programs_;
  GLuint vertex_array_ = 0;
  std::vector<Page> pages_;
  std::vector<SurfaceSamples> samples_;  // of the last prepare()
  gl::PixelBuffer results_;              // read-backs land here; grown, never shrunk
  gl::DeviceTimer timer_;
  double read_back_device_s_ = 0;
};

}  // namespace nurbs::glsl_deboor
