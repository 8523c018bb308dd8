#include "strategies/glu_nurbs/glu_nurbs.h"

#include "reference/trim_classify.h"
#include "reference/validation.h"

#if NURBSBENCH_HAVE_GLU
#include <GL/glu.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#endif

namespace nurbs {
namespace {

Capabilities glu_nurbs_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;  // libnurbs' MAXORDER is 24
  c.fp64 = false;             // GLU's knots, control points and arithmetic are GLfloat
  // GLU's automatic normals (GLU_NURBS_NORMAL) were measured and are not offered: GLU evaluates
  // each Bezier patch on its own, so a vertex on a C0 knot line comes with each side's normal
  // (131 deg off the reference's one-sided convention on `creases`, 24 deg on `degree-1`), and at
  // collapsed edges it has no limit rule (26 deg at the `sphere` poles). A positions-only baseline,
  // as in 000's Fig 8.
  c.normals = false;
  // GLU decides where it samples (per Bezier patch, GLU_DOMAIN_DISTANCE); only a grid request's
  // density can be passed on, never a span grid or a list of (u, v).
  c.sampling.span_grid = false;
  c.sampling.explicit_list = false;
  c.chooses_own_samples = true;
  return c;
}

#if NURBSBENCH_HAVE_GLU

// What the callbacks of one gluNurbsSurface hand back. GLU calls the texture-coordinate callback
// before the vertex callback of the same vertex (as glTexCoord precedes glVertex in immediate
// mode), so the vertex callback appends the current (u, v).
struct Capture {
  std::array<float, 2> uv{};
  std::vector<float> uvs, positions;
};

void GLAPIENTRY on_texture_coord(GLfloat* uv, void* data) {
  auto& c = *static_cast<Capture*>(data);
  c.uv = {uv[0], uv[1]};
}

void GLAPIENTRY on_vertex(GLfloat* p, void* data) {
  auto& c = *static_cast<Capture*>(data);
  c.uvs.insert(c.uvs.end(), c.uv.begin(), c.uv.end());
  c.positions.insert(c.positions.end(), p, p + 3);
}

// GLU_NURBS_ERROR has no user-data variant; evaluate() runs on one thread at a time.
thread_local GLenum glu_error = 0;
void GLAPIENTRY on_error(GLenum code) {
  if (glu_error == 0) glu_error = code;
}

// A trim curve as GLU takes it: a polyline (gluPwlCurve) for a degree-1 curve with unit weights,
// whose control polygon is the curve; otherwise gluNurbsCurve with (u, v) points
// (GLU_MAP1_TRIM_2) or, when rational, homogeneous (u w, v w, w) points (GLU_MAP1_TRIM_3).
struct GluTrimCurve {
  bool polyline = false;
  std::vector<GLfloat> knots, points;
  GLint order = 0, stride = 2;
  GLenum type = GLU_MAP1_TRIM_2;
};
using GluTrimLoop = std::vector<GluTrimCurve>;

// The curve run backwards: the same points, t -> a + b - t.
TrimCurve reversed(const TrimCurve& c) {
  TrimCurve r = c;
  std::reverse(r.points.begin(), r.points.end());
  std::reverse(r.weights.begin(), r.weights.end());
  const double a = c.knots.front(), b = c.knots.back();
  for (std::size_t k = 0; k < c.knots.size(); ++k)
    r.knots[k] = a + b - c.knots[c.knots.size() - 1 - k];
  return r;
}

// Twice the signed area of the loop's control polygon (every curve's points in order): positive
// when counter-clockwise. A curve turns the way its control polygon turns (variation diminishing),
// and the polygon of lines is the loop itself.
double control_polygon_area(const TrimLoop& loop) {
  std::vector<Point2> polygon;
  for (const TrimCurve& c : loop.curves)
    polygon.insert(polygon.end(), c.points.begin(), c.points.end());
  double twice_area = 0;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Point2& a = polygon[k];
    const Point2& b = polygon[(k + 1) % polygon.size()];
    twice_area += a[0] * b[1] - b[0] * a[1];
  }
  return twice_area;
}

// GLU keeps the region to the left of each trim curve (outer loops counter-clockwise, holes
// clockwise), where the scene's rule is even-odd and orientation-free. The two agree when a loop
// nested inside an even number of others (depth 0, 2, ...: a boundary of the face's outside) runs
// counter-clockwise and one inside an odd number (a hole) clockwise: the depth is counted with the
// reference's even-odd classifier (a point of the loop against each other loop alone), the
// direction from the signed area of the loop's control polygon, and a loop the wrong way round is
// reversed.
std::vector<TrimLoop> glu_oriented_loops(const Trim& trim) {
  std::vector<TrimLoop> loops = trim.loops;
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const Point2 on_loop = trim.loops[i].curves.front().points.front();
    SurfaceSamples at;
    at.tensor = false;
    at.u = {on_loop[0]};
    at.v = {on_loop[1]};
    int depth = 0;
    for (std::size_t j = 0; j < trim.loops.size(); ++j) {
      if (j == i) continue;
      Trim alone = trim;
      alone.loops = {trim.loops[j]};
      depth += classify_trim_samples(alone, at, false, TrimScalar::f64, 1).inside[0];
    }
    const bool counter_clockwise = control_polygon_area(loops[i]) > 0;
    if (counter_clockwise != (depth % 2 == 0)) {
      std::reverse(loops[i].curves.begin(), loops[i].curves.end());
      for (TrimCurve& c : loops[i].curves) c = reversed(c);
    }
  }
  return loops;
}

// GLU tessellates a trim curve of degree >= 2 by converting each of its Bézier arcs to the power
// basis through a constant table of Bernstein-to-power matrices for orders 1 to 8 (Mesa libGLU,
// libnurbs/internals/arctess.cc: ArcTessellator::gl_Bernstein, read as gl_Bernstein[order - 1] by
// trim_power_coeffs, unchecked). An arc of order 9 or more reads past the table: garbage or
// SIGSEGV in gluEndSurface, never a GLU error (bearing.iges face-163, a degree-8 p-curve, crashed
// this way). Degree-1 curves take the linear path and surfaces another one; neither uses it.
constexpr int kGluMaxTrimDegree = 7;

// RefusedError naming the first trim curve GLU cannot tessellate, if any.
void refuse_trims_beyond_glu(const Scene& scene) {
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    if (!s.trim) continue;
    for (std::size_t l = 0; l < s.trim->loops.size(); ++l)
      for (std::size_t k = 0; k < s.trim->loops[l].curves.size(); ++k)
        if (const int degree = s.trim->loops[l].curves[k].degree; degree > kGluMaxTrimDegree)
          throw RefusedError(fmt::format(
              "surface '{}' (#{}): trim.loops[{}].curves[{}].degree = {}: GLU tessellates trim "
              "curves up to degree {} (libnurbs' Bernstein-to-power table ends at order {}; a "
              "higher order reads past it and crashes)",
              s.name, i, l, k, degree, kGluMaxTrimDegree, kGluMaxTrimDegree + 1));
  }
}

GluTrimCurve make_glu_trim_curve(const TrimCurve& c) {
  GluTrimCurve g;
  const bool rational =
      std::any_of(c.weights.begin(), c.weights.end(), [](double w) { return w != 1.0; });
  g.polyline = c.degree == 1 && !rational && c.knots.front() == c.knots[1] &&
               c.knots.back() == c.knots[c.knots.size() - 2];
  g.order = c.degree + 1;
  g.stride = rational ? 3 : 2;
  g.type = rational ? GLU_MAP1_TRIM_3 : GLU_MAP1_TRIM_2;
  g.knots.assign(c.knots.begin(), c.knots.end());
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    const double w = rational ? c.weights[k] : 1.0;
    g.points.push_back(static_cast<GLfloat>(c.points[k][0] * w));
    g.points.push_back(static_cast<GLfloat>(c.points[k][1] * w));
    if (rational) g.points.push_back(static_cast<GLfloat>(w));
  }
  return g;
}

// One surface as GLU takes it: float knots, control points homogeneous (x w, y w, z w, w) for
// GL_MAP2_VERTEX_4 when rational, Cartesian for GL_MAP2_VERTEX_3 when not, u-major (the scene's
// order: s_stride = count_v * coordinates); plus the degree-1 texture-coordinate surface whose
// control points are the domain's corners, so that its value at (u, v) is (u, v).
struct GluSurface {
  std::vector<GLfloat> knots_u, knots_v, points;
  GLint coordinates = 3;
  GLenum type = GL_MAP2_VERTEX_3;
  GLint order_u = 0, order_v = 0, count_v = 0;
  std::array<GLfloat, 4> domain_knots_u{}, domain_knots_v{};
  std::array<GLfloat, 8> domain_corners{};
  GLfloat step_u = 1, step_v = 1;  // GLU_U_STEP/GLU_V_STEP: samples per unit parameter length
  double u_min = 0, u_max = 0, v_min = 0, v_max = 0;
  std::vector<GluTrimLoop> trim_loops;  // oriented for GLU (glu_oriented_loops)
};

GluSurface make_glu_surface(const Surface& s, const Sampling& grid) {
  GluSurface g;
  g.knots_u.assign(s.knots_u.begin(), s.knots_u.end());
  g.knots_v.assign(s.knots_v.begin(), s.knots_v.end());
  const bool rational = s.is_rational();
  g.coordinates = rational ? 4 : 3;
  g.type = rational ? GL_MAP2_VERTEX_4 : GL_MAP2_VERTEX_3;
  g.order_u = s.degree_u + 1;
  g.order_v = s.degree_v + 1;
  g.count_v = s.count_v;
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) {
      const Point3& p = s.point(i, j);
      const double w = rational ? s.weight(i, j) : 1.0;
      for (int c = 0; c < 3; ++c) g.points.push_back(static_cast<GLfloat>(p[c] * w));
      if (rational) g.points.push_back(static_cast<GLfloat>(w));
    }
  g.u_min = s.u_min();
  g.u_max = s.u_max();
  g.v_min = s.v_min();
  g.v_max = s.v_max();
  const auto u0 = static_cast<GLfloat>(g.u_min), u1 = static_cast<GLfloat>(g.u_max);
  const auto v0 = static_cast<GLfloat>(g.v_min), v1 = static_cast<GLfloat>(g.v_max);
  g.domain_knots_u = {u0, u0, u1, u1};
  g.domain_knots_v = {v0, v0, v1, v1};
  // corner (a, b), a along u: s_stride 4, t_stride 2.
  g.domain_corners = {u0, v0, u0, v1, u1, v0, u1, v1};
  // The requested grid has NU - 1 steps over the domain; GLU rounds the count per Bezier patch
  // up, so it samples at least that densely, and every knot lies on a sample.
  g.step_u = static_cast<GLfloat>((grid.grid_u - 1) / (g.u_max - g.u_min));
  g.step_v = static_cast<GLfloat>((grid.grid_v - 1) / (g.v_max - g.v_min));
  if (s.trim)
    for (const TrimLoop& loop : glu_oriented_loops(*s.trim)) {
      GluTrimLoop& glu_loop = g.trim_loops.emplace_back();
      for (const TrimCurve& c : loop.curves) glu_loop.push_back(make_glu_trim_curve(c));
    }
  return g;
}

std::string glu_error_text(GLenum code) {
  const GLubyte* text = gluErrorString(code);
  return text ? reinterpret_cast<const char*>(text) : fmt::format("GLU error {}", code);
}

class GluNurbsStrategy final : public Strategy {
 public:
  GluNurbsStrategy() : renderer_(gluNewNurbsRenderer()) {
    if (!renderer_) throw std::runtime_error("gluNewNurbsRenderer returned null");
    gluNurbsProperty(renderer_, GLU_NURBS_MODE, GLU_NURBS_TESSELLATOR);
    // No GL context: never read GL's matrices (only the screen-space sampling methods need them).
    gluNurbsProperty(renderer_, GLU_AUTO_LOAD_MATRIX, GL_FALSE);
    gluNurbsProperty(renderer_, GLU_CULLING, GL_FALSE);
    gluNurbsProperty(renderer_, GLU_SAMPLING_METHOD, GLU_DOMAIN_DISTANCE);
    // The casts to GLU's void(*)() callback type are how GLU's API is meant to be used.
    gluNurbsCallback(renderer_, GLU_NURBS_ERROR, reinterpret_cast<_GLUfuncptr>(on_error));
    gluNurbsCallback(renderer_, GLU_NURBS_TEXTURE_COORD_DATA,
                     reinterpret_cast<_GLUfuncptr>(on_texture_coord));
    gluNurbsCallback(renderer_, GLU_NURBS_VERTEX_DATA, reinterpret_cast<_GLUfuncptr>(on_vertex));
  }
  ~GluNurbsStrategy() override { gluDeleteNurbsRenderer(renderer_); }
  GluNurbsStrategy(const GluNurbsStrategy&) = delete;
  GluNurbsStrategy& operator=(const GluNurbsStrategy&) = delete;

  std::string_view name() const override { return "glu-nurbs"; }
  Capabilities capabilities() const override { return glu_nurbs_capabilities(); }
  DeviceInfo device() const override {
    const GLubyte* version = gluGetString(GLU_VERSION);
    return {"host CPU, 1 thread",
            "cpu",
            {{"library", fmt::format("GLU {} (GLU_NURBS_TESSELLATOR, GLU_DOMAIN_DISTANCE)",
                                     version ? reinterpret_cast<const char*>(version) : "?")}}};
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    refuse_trims_beyond_glu(scene);
    request_ = request;
    surfaces_.clear();
    for (const Surface& s : scene.surfaces)
      surfaces_.push_back(make_glu_surface(s, request.sampling));
    captures_.resize(surfaces_.size());
  }

  void evaluate() override {
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      GluSurface& g = surfaces_[i];
      Capture& c = captures_[i];
      c.uvs.clear();
      c.positions.clear();
      glu_error = 0;
      gluNurbsCallbackData(renderer_, &c);
      gluNurbsProperty(renderer_, GLU_U_STEP, g.step_u);
      gluNurbsProperty(renderer_, GLU_V_STEP, g.step_v);
      gluBeginSurface(renderer_);
      gluNurbsSurface(renderer_, static_cast<GLint>(g.knots_u.size()), g.knots_u.data(),
                      static_cast<GLint>(g.knots_v.size()), g.knots_v.data(),
                      g.count_v * g.coordinates, g.coordinates, g.points.data(), g.order_u,
                      g.order_v, g.type);
      gluNurbsSurface(renderer_, 4, g.domain_knots_u.data(), 4, g.domain_knots_v.data(), 4, 2,
                      g.domain_corners.data(), 2, 2, GL_MAP2_TEXTURE_COORD_2);
      for (GluTrimLoop& loop : g.trim_loops) {
        gluBeginTrim(renderer_);
        for (GluTrimCurve& c : loop)
          if (c.polyline)
            gluPwlCurve(renderer_, static_cast<GLint>(c.points.size() / 2), c.points.data(), 2,
                        GLU_MAP1_TRIM_2);
          else
            gluNurbsCurve(renderer_, static_cast<GLint>(c.knots.size()), c.knots.data(), c.stride,
                          c.points.data(), c.order, c.type);
        gluEndTrim(renderer_);
      }
      gluEndSurface(renderer_);
      if (glu_error != 0)
        throw std::runtime_error(
            fmt::format("GLU NURBS error on surface {}: {}", i, glu_error_text(glu_error)));
    }
  }

  // The distinct vertices GLU produced (its triangle strips repeat most of them): identical
  // (u, v, position) tuples are kept once, anything GLU produced differently at the same
  // (u, v) is kept and measured. Parameters come back as GLU evaluated them (float), clamped to
  // the double domain where float rounding of the domain's ends puts them just outside it.
  EvalResult read_back() override {
    EvalResult out;
    out.surfaces.resize(surfaces_.size());
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const Capture& c = captures_[i];
      const GluSurface& g = surfaces_[i];
      const std::size_t n = c.positions.size() / 3;
      // Bit patterns: a total order even with NaN, and "identical" means bit for bit.
      auto key = [&](std::size_t k, std::size_t f) {
        return std::bit_cast<std::uint32_t>(f < 2 ? c.uvs[2 * k + f] : c.positions[3 * k + f - 2]);
      };
      std::vector<std::size_t> order(n);
      std::iota(order.begin(), order.end(), std::size_t{0});
      auto less = [&](std::size_t a, std::size_t b) {
        for (std::size_t f = 0; f < 5; ++f)
          if (key(a, f) != key(b, f)) return key(a, f) < key(b, f);
        return false;
      };
      auto same = [&](std::size_t a, std::size_t b) { return !less(a, b) && !less(b, a); };
      std::sort(order.begin(), order.end(), less);
      order.erase(std::unique(order.begin(), order.end(), same), order.end());

      SurfaceResult& r = out.surfaces[i];
      r.samples.tensor = false;
      r.samples.u.resize(order.size());
      r.samples.v.resize(order.size());
      r.positions = PointArray(Precision::f32, order.size());
      for (std::size_t k = 0; k < order.size(); ++k) {
        const std::size_t s = order[k];
        r.samples.u[k] = std::clamp(static_cast<double>(c.uvs[2 * s]), g.u_min, g.u_max);
        r.samples.v[k] = std::clamp(static_cast<double>(c.uvs[2 * s + 1]), g.v_min, g.v_max);
        std::copy_n(&c.positions[3 * s], 3, r.positions.f32() + 3 * k);
      }
    }
    return out;
  }

 private:
  GLUnurbs* renderer_;
  EvalRequest request_;
  std::vector<GluSurface> surfaces_;
  std::vector<Capture> captures_;
};

#endif

}  // namespace

StrategyEntry glu_nurbs_entry() {
  return {"glu-nurbs",
          "GLU gluNurbsSurface tessellator (000 Fig 8 baseline), GLU_DOMAIN_DISTANCE sampling",
          "baseline",
          [] {
#if NURBSBENCH_HAVE_GLU
            return Availability{true, ""};
#else
            return Availability{false, "not built with GLU (libglu1-mesa-dev)"};
#endif
          },
          glu_nurbs_capabilities,
          [](const StrategyOptions&) -> std::unique_ptr<Strategy> {
#if NURBSBENCH_HAVE_GLU
            return std::make_unique<GluNurbsStrategy>();
#else
            throw std::runtime_error("not built with GLU (libglu1-mesa-dev)");
#endif
          }};
}

}  // namespace nurbs
