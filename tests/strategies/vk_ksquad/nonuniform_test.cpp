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

TEST(vk_ksquad_nonuniform, DecisionsAreTheEquations) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  std::size_t crease_flagged = 0, g1_flagged = 0, all_linear = 0, all_culled = 0;
  for (const Case& c : cases()) {
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
    const double mu = settings.mu * 4, cap = settings.max_level;
    const double epsilon = settings.epsilon, eta = settings.eta;
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
      const double x0 = s.knots_u[p.span_u], x1 = s.knots_u[p.span_u + 1];
      const double y0 = s.knots_v[p.span_v], y1 = s.knots_v[p.span_v + 1];
      // eq. 3 per edge: u = x_i, v = y_j, u = x_i+1, v = y_j+1
      std::array<double, 2> corner[2][2];
      for (int du = 0; du < 2; ++du)
        for (int dv = 0; dv < 2; ++dv)
          corner[du][dv] = pixels(to_clip(camera, surface_point(net, du ? x1 : x0, dv ? y1 : y0)),
                                  width, height);
      const std::array<double, 2>* ends[4][2] = {{&corner[0][0], &corner[0][1]},
                                                 {&corner[0][0], &corner[1][0]},
                                                 {&corner[1][0], &corner[1][1]},
                                                 {&corner[0][1], &corner[1][1]}};
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
        // S' the bilinear interpolation of the cell's corners
        Margin linear_margin;
        int depth_linear = kDepth;
        for (int d = kDepth - 1; d >= 0; --d) {  // every depth's margins; the smallest pass wins
          const int step = (kLattice - 1) >> d, h = step / 2;
          bool pass = true;
          for (int a = 0; a < kLattice - 1; a += step)
            for (int b = 0; b < kLattice - 1; b += step) {
              const V3 &c00 = lattice[a][b], &c10 = lattice[a + step][b],
                       &c01 = lattice[a][b + step], &c11 = lattice[a + step][b + step];
              const auto half = [](const V3& p, const V3& q) {
                return V3{(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2};
              };
              const std::pair<std::array<int, 2>, V3> tests[5] = {
                  {{a + h, b + h}, half(half(c00, c10), half(c01, c11))},
                  {{a + h, b}, half(c00, c10)},
                  {{a, b + h}, half(c00, c01)},
                  {{a + step, b + h}, half(c10, c11)},
                  {{a + h, b + step}, half(c01, c11)}};
              for (const auto& [at, linear] : tests) {
                const double dev = pixel_distance(screen[at[0]][at[1]],
                                                  pixels(to_clip(camera, linear), width, height));
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
