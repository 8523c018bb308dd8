// vk-ksquad nonuniform mode against 003 §3.1's equations computed here on the CPU in double,
// independently of the strategy's code: eq. 3's per-edge levels (at vk-mu x 4, the control
// stage's lower level) and the lattice they give, then per KSDie the Exact Visible Set culling
// (view frustum, back face), eq. 4's and eq. 5's subdivision depths and the f tag from friend
// surfaces found here -- all from the reference evaluator -- compared with the geometry stage's
// records; integer decisions must be equal except where the double value is within a small float
// margin of its threshold (counted and bounded). Then the emitted vertices against the reference:
// on the surface within the float budget, normals within a degree.
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "reference/nurbs_math.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "strategies/vk_ksquad/ksquad_settings.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"

namespace nurbs {
namespace {

constexpr int kDepth = 2;    // ksquad_nonuniform.geom's subdivision bound (003 leaves it open)
constexpr int kLattice = 5;  // 2^kDepth + 1
constexpr double kPixelMargin = 2e-3;  // float pixel positions vs double near a threshold

using V3 = Vec3<double>;

// Two biquadratic Bézier patches side by side, x in [0, 1] and [1, 2], y in [0, 1]; z = c(x) +
// d(y). The second patch's first control-point step across the shared edge x = 1 continues the
// first's last (G1, indeed C1), or turns down (a crease).
Scene two_patches(bool g1) {
  Scene scene;
  scene.name = g1 ? "two-g1" : "two-crease";
  const double c[2][3] = {{0, 0.3, 0.4}, {0.4, g1 ? 0.5 : 0.1, g1 ? 0.3 : 0.0}};
  const double d[3] = {0, 0.3, 0};
  for (int k = 0; k < 2; ++k) {
    Surface s;
    s.name = k == 0 ? "left" : "right";
    s.degree_u = s.degree_v = 2;
    s.count_u = s.count_v = 3;
    s.knots_u = s.knots_v = {0, 0, 0, 1, 1, 1};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) s.points.push_back({k + 0.5 * i, 0.5 * j, c[k][i] + d[j]});
    s.weights.assign(9, 1.0);
    scene.surfaces.push_back(s);
  }
  return scene;
}

double dist(const V3& a, const V3& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

// Friends, our own way: two domain sides are shared when their ends and middle coincide (either
// direction), friends when the unit normals at 17 points along them are parallel within 0.5
// degree. Bit e of a surface's mask: side e (u = lo, v = lo, u = hi, v = hi) shared with a surface
// that is not a friend.
std::vector<int> non_friend_sides(const Scene& scene, double tolerance) {
  const auto side_point = [](const Surface& s, int e, double t, bool normal) {
    const SurfaceNet<double> net(s);
    const double u = e == 0   ? s.u_min()
                     : e == 2 ? s.u_max()
                              : s.u_min() + t * (s.u_max() - s.u_min());
    const double v = e == 1   ? s.v_min()
                     : e == 3 ? s.v_max()
                              : s.v_min() + t * (s.v_max() - s.v_min());
    return normal ? surface_normal(net, u, v) : surface_point(net, u, v);
  };
  std::vector<int> mask(scene.surfaces.size(), 0);
  for (std::size_t a = 0; a < scene.surfaces.size(); ++a)
    for (std::size_t b = 0; b < scene.surfaces.size(); ++b)
      for (int e = 0; e < 4; ++e)
        for (int f = 0; f < 4; ++f)
          for (int flip = 0; flip < 2; ++flip) {
            if (a == b) continue;
            const Surface &sa = scene.surfaces[a], &sb = scene.surfaces[b];
            const auto t_b = [&](double t) { return flip ? 1 - t : t; };
            bool shared = true;
            for (double t : {0.0, 0.5, 1.0})
              shared = shared && dist(side_point(sa, e, t, false),
                                      side_point(sb, f, t_b(t), false)) <= tolerance;
            if (!shared) continue;
            for (int k = 0; k <= 16; ++k) {
              const V3 n = side_point(sa, e, k / 16.0, true),
                       m = side_point(sb, f, t_b(k / 16.0), true);
              if (norm(n) < 0.5 || norm(m) < 0.5) continue;
              if (norm(cross(n, m)) > std::sin(0.5 * M_PI / 180)) mask[a] |= 1 << e;
            }
          }
  return mask;
}

// The point a cell renders at the fraction (s, t) of its parameter rectangle, the cell not
// subdivided further: the geometry stage emits each cell as a triangle strip of its lattice rows,
// (0,0) (0,1) (1,0) (1,1) in (u, v) corner indices, i.e. the triangles (0,0) (0,1) (1,0) and
// (0,1) (1,0) (1,1). The triangle holding (s, t) in the parameter rectangle, by its barycentric
// coordinates there, weights that triangle's world-space corners: what the rasterizer draws at
// (s, t) (it interpolates the projected triangle perspective-correctly, so p() of this point is
// where (s, t) appears on screen). c[du][dv]: the corner at (du, dv).
V3 rendered_point(const V3 c[2][2], double s, double t) {
  const std::array<int, 2> triangles[2][3] = {{{0, 0}, {0, 1}, {1, 0}}, {{0, 1}, {1, 0}, {1, 1}}};
  for (const auto& tri : triangles) {
    const double x0 = tri[0][0], y0 = tri[0][1], x1 = tri[1][0], y1 = tri[1][1], x2 = tri[2][0],
                 y2 = tri[2][1];
    const double det = (y1 - y2) * (x0 - x2) + (x2 - x1) * (y0 - y2);
    const double l0 = ((y1 - y2) * (s - x2) + (x2 - x1) * (t - y2)) / det;
    const double l1 = ((y2 - y0) * (s - x2) + (x0 - x2) * (t - y2)) / det;
    const double l2 = 1 - l0 - l1;
    if (l0 < -1e-12 || l1 < -1e-12 || l2 < -1e-12) continue;
    const double l[3] = {l0, l1, l2};
    V3 p{0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) p[d] += l[k] * c[tri[k][0]][tri[k][1]][d];
    return p;
  }
  ADD_FAILURE() << "(" << s << ", " << t << ") outside the cell";
  return c[0][0];
}

struct Clip {
  double x, y, z, w;
};
Clip to_clip(const std::array<float, 16>& m, const V3& p) {
  double c[4];
  for (int r = 0; r < 4; ++r) c[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
  return {c[0], c[1], c[2], c[3]};
}
// eq. 3's p(): pixels; +inf behind the eye
std::array<double, 2> pixels(const Clip& c, double width, double height) {
  if (c.w <= 0) return {std::numeric_limits<double>::infinity(), 0};
  return {c.x / c.w * 0.5 * width, c.y / c.w * 0.5 * height};
}
double pixel_distance(const std::array<double, 2>& a, const std::array<double, 2>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1]);
}

// vk-thresholds=surface, from its definition (ksquad_settings.h): per surface, the diagonal of
// the pixel box of its projected control points over the scene's, within [1/64, 1]; 1 where a
// control point is behind the eye. All 1 for vk-thresholds=global.
std::vector<double> threshold_scales(const Scene& scene, const std::array<float, 16>& camera,
                                     double width, double height, bool per_surface) {
  std::vector<double> out(scene.surfaces.size(), 1.0);
  if (!per_surface) return out;
  std::vector<std::array<double, 4>> boxes;  // x lo, y lo, x hi, y hi; empty when behind
  std::array<double, 4> scene_box{1e300, 1e300, -1e300, -1e300};
  for (const Surface& s : scene.surfaces) {
    std::array<double, 4> box{1e300, 1e300, -1e300, -1e300};
    for (const auto& p : s.points) {
      const Clip c = to_clip(camera, V3{p[0], p[1], p[2]});
      if (!(c.w > 0)) {
        box = {0, 0, -1, -1};
        break;
      }
      const auto px = pixels(c, width, height);
      box = {std::min(box[0], px[0]), std::min(box[1], px[1]), std::max(box[2], px[0]),
             std::max(box[3], px[1])};
    }
    boxes.push_back(box);
    if (box[2] >= box[0])
      scene_box = {std::min(scene_box[0], box[0]), std::min(scene_box[1], box[1]),
                   std::max(scene_box[2], box[2]), std::max(scene_box[3], box[3])};
  }
  const double whole = std::hypot(scene_box[2] - scene_box[0], scene_box[3] - scene_box[1]);
  for (std::size_t i = 0; i < boxes.size(); ++i)
    if (boxes[i][2] >= boxes[i][0])
      out[i] = std::clamp(std::hypot(boxes[i][2] - boxes[i][0], boxes[i][3] - boxes[i][1]) / whole,
                          1.0 / 64, 1.0);
  return out;
}

// A decision from values compared with a threshold: the smallest |value - threshold| seen, so a
// disagreement there can be told from a wrong decision.
struct Margin {
  double closest = std::numeric_limits<double>::infinity();
  void saw(double value, double threshold) {
    if (std::isfinite(value)) closest = std::min(closest, std::abs(value - threshold));
  }
};

struct Tally {
  std::size_t ksdice = 0, borderline = 0, mismatched = 0, linear = 0, boundary = 0, culled = 0,
              flagged = 0, skipped = 0;
};

struct Case {
  const char* label;
  Scene scene;
  std::map<std::string, std::string> options;
};

// The case's strategy after prepare() and evaluate().
std::unique_ptr<Strategy> evaluated(const Case& c, bool normals) {
  StrategyOptions options;
  options.extra = c.options;
  auto strategy = make_vk_ksquad(options);
  strategy->prepare(c.scene, EvalRequest{Sampling{}, Precision::f32, normals});
  strategy->evaluate();
  return strategy;
}

std::vector<Case> cases() {
  std::vector<Case> out;
  out.push_back({"patch144", *make_builtin_scene("patch144"), {{"vk-epsilon", "0.25"}}});
  out.push_back({"two-g1", two_patches(true), {{"vk-eta", "2"}}});
  out.push_back({"two-crease", two_patches(false), {{"vk-eta", "2"}}});
  out.push_back({"teapot", *make_builtin_scene("teapot"), {{"vk-mu", "3"}}});
  for (Case& c : out) c.options["vk-mode"] = "nonuniform";
  return out;
}

// The decisions again under eq. 3's literal reading and per-surface thresholds (not emitted
// vertices: those are the same code as above).
std::vector<Case> decision_cases() {
  std::vector<Case> out = cases();
  out.push_back({"teapot literal, per-surface",
                 *make_builtin_scene("teapot"),
                 {{"vk-mode", "nonuniform"},
                  {"vk-mu", "3"},
                  {"vk-eq3", "literal"},
                  {"vk-thresholds", "surface"}}});
  return out;
}

TEST(vk_ksquad_nonuniform, DecisionsAreTheEquations) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  std::size_t crease_flagged = 0, g1_flagged = 0, all_linear = 0, all_culled = 0;
  for (const Case& c : decision_cases()) {
    SCOPED_TRACE(c.label);
    const auto strategy = evaluated(c, false);
    const std::vector<PatchLevels> levels = ksquad_patch_levels(*strategy);
    const std::vector<KsdieRecord> records = ksquad_ksdice(*strategy);
    const KsquadStatistics st = ksquad_statistics(*strategy);
    strategy->read_back();
    const auto details = strategy->device().details;

    StrategyOptions options;
    options.extra = c.options;
    const vk_ksquad::KsquadSettings settings = vk_ksquad::ksquad_settings(options);
    const std::array<float, 16> camera = vk_ksquad::scene_camera(c.scene, settings);
    const double width = settings.viewport[0], height = settings.viewport[1];
    const double cap = settings.max_level;
    const auto literal = c.options.find("vk-eq3");
    const bool eq3_literal = literal != c.options.end() && literal->second == "literal";
    const auto thresholds = c.options.find("vk-thresholds");
    const std::vector<double> scale =
        threshold_scales(c.scene, camera, width, height,
                         thresholds != c.options.end() && thresholds->second == "surface");
    const std::vector<int> friendless =
        non_friend_sides(c.scene, 1e-6 * c.scene.bounding_box_diagonal());

    std::map<std::tuple<int, int, int>, std::vector<const KsdieRecord*>> by_quad;
    for (const KsdieRecord& r : records) by_quad[{r.surface, r.span_u, r.span_v}].push_back(&r);
    Tally t;
    std::size_t device_linear = 0, device_boundary = 0, device_culled = 0, device_triangles = 0;
    for (const KsdieRecord& r : records) {
      device_culled += r.status >= 2;
      if (r.status != 1) continue;
      device_linear += r.depth_linear > 0;
      device_boundary += r.depth_boundary > 0;
      device_triangles += 2u << (2 * std::max(r.depth_linear, r.depth_boundary));
    }
    for (const PatchLevels& p : levels) {
      const Surface& s = c.scene.surfaces[p.surface];
      const SurfaceNet<double> net(s);
      const double mu = settings.mu * 4 * scale[p.surface];
      const double epsilon = settings.epsilon * scale[p.surface],
                   eta = settings.eta * scale[p.surface];
      const double x0 = s.knots_u[p.span_u], x1 = s.knots_u[p.span_u + 1];
      const double y0 = s.knots_v[p.span_v], y1 = s.knots_v[p.span_v + 1];
      // eq. 3 per edge: u = x_i, v = y_j, u = x_i+1, v = y_j+1
      std::array<double, 2> corner[2][2];
      for (int du = 0; du < 2; ++du)
        for (int dv = 0; dv < 2; ++dv)
          corner[du][dv] = pixels(to_clip(camera, surface_point(net, du ? x1 : x0, dv ? y1 : y0)),
                                  width, height);
      // literal: "k < m and l < n" leaves the diagonal pair, for every edge
      const std::array<double, 2>* ends[4][2] = {{&corner[0][0], &corner[0][1]},
                                                 {&corner[0][0], &corner[1][0]},
                                                 {&corner[1][0], &corner[1][1]},
                                                 {&corner[0][1], &corner[1][1]}};
      if (eq3_literal)
        for (auto& e : ends) {
          e[0] = &corner[0][0];
          e[1] = &corner[1][1];
        }
      bool borderline_levels = false;
      double want[4];
      for (int e = 0; e < 4; ++e) {
        const double ratio = pixel_distance(*ends[e][0], *ends[e][1]) / mu;
        want[e] =
            std::isfinite(ratio) ? std::floor(ratio) + 1 : std::numeric_limits<double>::infinity();
        if (p.wanted[e] == want[e]) continue;
        if (std::abs(ratio - std::round(ratio)) <= 1e-4 * std::max(1.0, ratio) &&
            std::abs(p.wanted[e] - want[e]) == 1) {
          borderline_levels = true;
        } else {
          ++t.mismatched;
          ADD_FAILURE() << "surface " << p.surface << " KSQuad (" << p.span_u << ", " << p.span_v
                        << ") edge " << e << ": device level " << p.wanted[e] << ", eq. 3 "
                        << want[e];
        }
      }
      const int level_u = static_cast<int>(std::min(std::max(want[1], want[3]), cap));
      const int level_v = static_cast<int>(std::min(std::max(want[0], want[2]), cap));
      const auto& dice = by_quad[{p.surface, p.span_u, p.span_v}];
      if (borderline_levels) {
        ++t.borderline;
        t.skipped += dice.size();
        continue;
      }
      EXPECT_EQ(p.set[1], level_u);
      EXPECT_EQ(p.set[0], level_v);
      ASSERT_EQ(dice.size(), static_cast<std::size_t>(level_u * level_v));
      for (const KsdieRecord* r : dice) {
        ++t.ksdice;
        // f: the KSDie's sides on the domain's sides, where the surface has no friend there
        int sides = 0;
        if (r->i == 0 && x0 == s.u_min()) sides |= 1;
        if (r->j == 0 && y0 == s.v_min()) sides |= 2;
        if (r->i == level_u - 1 && x1 == s.u_max()) sides |= 4;
        if (r->j == level_v - 1 && y1 == s.v_max()) sides |= 8;
        const int f = sides & friendless[p.surface];
        EXPECT_EQ(r->f, f) << "KSDie (" << r->i << ", " << r->j << ")";
        t.flagged += f != 0;
        V3 lattice[kLattice][kLattice];
        std::array<double, 2> screen[kLattice][kLattice];
        for (int a = 0; a < kLattice; ++a)
          for (int b = 0; b < kLattice; ++b) {
            const double u = x0 + (x1 - x0) * (r->i + a / 4.0) / level_u;
            const double v = y0 + (y1 - y0) * (r->j + b / 4.0) / level_v;
            lattice[a][b] = surface_point(net, u, v);
            screen[a][b] = pixels(to_clip(camera, lattice[a][b]), width, height);
          }
        // EVS: frustum (all four corners outside one clip plane), then back face (the projected
        // quad (0,0) (1,0) (1,1) (0,1) with positive signed area in the pixel frame)
        const Clip q[4] = {to_clip(camera, lattice[0][0]), to_clip(camera, lattice[4][0]),
                           to_clip(camera, lattice[4][4]), to_clip(camera, lattice[0][4])};
        Margin cull_margin;
        int expected = 1;
        for (int plane = 0; plane < 6 && expected == 1; ++plane) {
          bool all_out = true;
          for (const Clip& k : q) {
            const double g[6] = {k.x - k.w, -k.w - k.x, k.y - k.w, -k.w - k.y, -k.z, k.z - k.w};
            all_out = all_out && g[plane] > 0;
            cull_margin.saw(g[plane] / (std::abs(k.w) + 1e-300), 0);
          }
          if (all_out) expected = 2;
        }
        if (expected == 1 && q[0].w > 0 && q[1].w > 0 && q[2].w > 0 && q[3].w > 0) {
          double area = 0, scale = 0;
          for (int k = 0; k < 4; ++k) {
            const auto a0 = pixels(q[k], width, height), a1 = pixels(q[(k + 1) % 4], width, height);
            area += a0[0] * a1[1] - a1[0] * a0[1];
            scale += std::abs(a0[0] * a1[1]) + std::abs(a1[0] * a0[1]);
          }
          cull_margin.saw(area / scale, 0);
          if (area > 0) expected = 3;
        }
        if (r->status != expected) {
          if (cull_margin.closest < 1e-5) {
            ++t.borderline;
          } else {
            ++t.mismatched;
            ADD_FAILURE() << "KSDie (" << r->i << ", " << r->j << ") of surface " << p.surface
                          << " KSQuad (" << p.span_u << ", " << p.span_v << "): status "
                          << r->status << ", EVS says " << expected;
          }
          continue;
        }
        if (expected != 1) {
          ++t.culled;
          continue;
        }
        // eq. 4: cells of depth d pass when |p(S) - p(S')| < ε at their centre and edge midpoints,
        // S' the point the cell renders there if not subdivided (rendered_point)
        Margin linear_margin;
        int depth_linear = kDepth;
        for (int d = kDepth - 1; d >= 0; --d) {  // every depth's margins; the smallest pass wins
          const int step = (kLattice - 1) >> d, h = step / 2;
          bool pass = true;
          for (int a = 0; a < kLattice - 1; a += step)
            for (int b = 0; b < kLattice - 1; b += step) {
              const V3 cell[2][2] = {{lattice[a][b], lattice[a][b + step]},
                                     {lattice[a + step][b], lattice[a + step][b + step]}};
              // the centre and the four edge midpoints, as fractions of the cell
              const std::array<int, 2> at[5] = {{1, 1}, {1, 0}, {0, 1}, {2, 1}, {1, 2}};
              for (const auto& half_steps : at) {
                const V3 rendered = rendered_point(cell, half_steps[0] / 2.0, half_steps[1] / 2.0);
                const double dev =
                    pixel_distance(screen[a + h * half_steps[0]][b + h * half_steps[1]],
                                   pixels(to_clip(camera, rendered), width, height));
                linear_margin.saw(dev, epsilon);
                pass = pass && dev < epsilon;
              }
            }
          if (pass) depth_linear = d;
        }
        // eq. 5 on the sides f marks
        Margin boundary_margin;
        int depth_boundary = 0;
        if (f != 0) {
          depth_boundary = kDepth;
          const int last = kLattice - 1;
          for (int d = 0; d < kDepth; ++d) {
            const int step = last >> d;
            bool pass = true;
            for (int k = 0; k < last; k += step) {
              const std::pair<int, double> edges[4] = {
                  {1, pixel_distance(screen[0][k], screen[0][k + step])},
                  {2, pixel_distance(screen[k][0], screen[k + step][0])},
                  {4, pixel_distance(screen[last][k], screen[last][k + step])},
                  {8, pixel_distance(screen[k][last], screen[k + step][last])}};
              for (const auto& [bit, length] : edges)
                if (f & bit) {
                  boundary_margin.saw(length, eta);
                  pass = pass && length < eta;
                }
            }
            if (pass) {
              depth_boundary = d;
              break;
            }
          }
        }
        t.linear += depth_linear > 0;
        t.boundary += depth_boundary > 0;
        const std::pair<int, int> got{r->depth_linear, r->depth_boundary};
        if (got != std::make_pair(depth_linear, depth_boundary)) {
          const bool near =
              (r->depth_linear == depth_linear || linear_margin.closest < kPixelMargin) &&
              (r->depth_boundary == depth_boundary || boundary_margin.closest < kPixelMargin);
          if (near) {
            ++t.borderline;
          } else {
            ++t.mismatched;
            ADD_FAILURE() << "KSDie (" << r->i << ", " << r->j << ") of surface " << p.surface
                          << " KSQuad (" << p.span_u << ", " << p.span_v << "): device depths "
                          << r->depth_linear << ", " << r->depth_boundary << "; eq. 4 "
                          << depth_linear << ", eq. 5 " << depth_boundary;
          }
        }
      }
    }
    EXPECT_EQ(t.mismatched, 0u);
    EXPECT_LE(t.borderline, t.ksdice / 100 + 1);
    EXPECT_EQ(st.ksdice, records.size());
    EXPECT_EQ(st.subdivided_linear, device_linear);
    EXPECT_EQ(st.subdivided_boundary, device_boundary);
    EXPECT_EQ(st.culled_frustum + st.culled_back, device_culled);
    EXPECT_EQ(st.triangles, device_triangles);
    EXPECT_EQ(details.at("vk_mode"), "nonuniform");
    EXPECT_EQ(details.at("nu_ksdice"), std::to_string(st.ksdice));
    EXPECT_EQ(details.at("nu_triangles"), std::to_string(st.triangles));
    if (std::string(c.label) == "two-crease") crease_flagged += t.flagged;
    if (std::string(c.label) == "two-g1") g1_flagged += t.flagged;
    all_linear += t.linear;
    all_culled += t.culled;
    if (std::string(c.label) == "two-crease") {
      EXPECT_EQ(friendless, (std::vector<int>{4, 1})) << "the crease is x = 1";
      EXPECT_GT(t.boundary, 0u) << "eq. 5 should subdivide along the crease";
    }
    if (std::string(c.label) == "two-g1") {
      EXPECT_EQ(friendless, (std::vector<int>{0, 0}));
    }
    std::cout << c.label << " nonuniform: " << t.ksdice << " KSDice checked (" << t.skipped
              << " on borderline levels), eq. 4 subdivided " << t.linear << ", eq. 5 " << t.boundary
              << ", culled " << t.culled << ", f set " << t.flagged << ", " << t.borderline
              << " borderline; device triangles " << st.triangles << "\n";
  }
  EXPECT_GT(crease_flagged, 0u);
  EXPECT_EQ(g1_flagged, 0u);
  EXPECT_GT(all_linear, 0u) << "some KSDie should fail eq. 4";
  EXPECT_GT(all_culled, 0u) << "some KSDie should be culled";
}

TEST(vk_ksquad_nonuniform, EmittedVerticesLieOnTheSurface) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  for (const Case& c : cases()) {
    SCOPED_TRACE(c.label);
    const auto strategy = evaluated(c, true);
    const EvalResult result = strategy->read_back();
    std::size_t expected_vertices = 0;
    for (const KsdieRecord& r : ksquad_ksdice(*strategy))
      if (r.status == 1) {
        const int n = (1 << std::max(r.depth_linear, r.depth_boundary)) + 1;
        expected_vertices += static_cast<std::size_t>(n * n);
      }
    double largest = 0;
    for (const Surface& s : c.scene.surfaces)
      for (const auto& p : s.points)
        for (double x : p) largest = std::max(largest, std::abs(x));
    const double tolerance = 16 * FLT_EPSILON * largest;
    std::size_t vertices = 0;
    double worst = 0, worst_angle = 0;
    for (std::size_t i = 0; i < result.surfaces.size(); ++i) {
      const SurfaceResult& r = result.surfaces[i];
      const SurfaceNet<double> net(c.scene.surfaces[i]);
      ASSERT_EQ(r.normals.size(), r.positions.size());
      for (std::size_t k = 0; k < r.samples.count(); ++k) {
        ++vertices;
        const double u = r.samples.u[k], v = r.samples.v[k];
        const V3 ref = surface_point(net, u, v);
        const float* p = r.positions.f32() + 3 * k;
        const double d = dist(ref, {p[0], p[1], p[2]});
        worst = std::max(worst, d);
        EXPECT_LE(d, tolerance) << "surface " << i << " (" << u << ", " << v << ")";
        const V3 n = surface_normal(net, u, v);
        const float* m = r.normals.f32() + 3 * k;
        const V3 md{m[0], m[1], m[2]};
        if (norm(n) < 0.5 || norm(md) < 0.5) continue;  // collapsed: no normal to compare
        const double dot = n[0] * md[0] + n[1] * md[1] + n[2] * md[2];
        const double angle = std::acos(std::clamp(dot / norm(md), -1.0, 1.0)) * 180 / M_PI;
        worst_angle = std::max(worst_angle, angle);
        EXPECT_LE(angle, 1.0) << "surface " << i << " (" << u << ", " << v << ")";
      }
    }
    EXPECT_EQ(vertices, expected_vertices);
    EXPECT_GT(vertices, 0u);
    std::cout << c.label << ": " << vertices << " emitted vertices, worst distance " << worst
              << " (budget " << tolerance << "), worst normal angle " << worst_angle << " deg\n";
  }
}

}  // namespace
}  // namespace nurbs
