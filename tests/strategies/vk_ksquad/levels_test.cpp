// vk-ksquad adaptive mode: the levels the control stage chose, against 003 eq. (3) computed here
// on the CPU in double from the equation -- the KSQuad corners S(x_k, y_l) by the reference,
// projected with the strategy's camera, tau = the smallest integer with dist / tau < mu -- so a
// wrong level function (or corners, or projection) on the device fails.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
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

struct Projected {
  double x = 0, y = 0;
  bool behind = false;
};

// p(): world -> pixels, as 003 §3.1 uses it (clip x, y over w, scaled by half the viewport).
Projected project(const std::array<float, 16>& m, const Vec3<double>& p, double width,
                  double height) {
  double clip[4];
  for (int r = 0; r < 4; ++r) clip[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
  return {clip[0] / clip[3] * 0.5 * width, clip[1] / clip[3] * 0.5 * height, clip[3] <= 0};
}

// Eq. (3) for one edge: tau with dist / tau < mu, the smallest such integer; +inf behind the
// eye. `ratio` returns dist / mu (to tell a borderline case).
double eq3_level(const Projected& a, const Projected& b, double mu, double& ratio) {
  if (a.behind || b.behind) return std::numeric_limits<double>::infinity();
  ratio = std::hypot(a.x - b.x, a.y - b.y) / mu;
  return std::floor(ratio) + 1;
}

struct LevelCase {
  const char* scene;
  std::map<std::string, std::string> options;
};

TEST(vk_ksquad_levels, AdaptiveLevelsAreEquation3) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  const LevelCase cases[] = {
      {"patch144", {{"vk-mode", "adaptive"}, {"vk-mu", "4"}}},
      {"torus", {{"vk-mode", "adaptive"}, {"vk-mu", "8"}}},
      {"teapot", {{"vk-mode", "adaptive"}, {"vk-mu", "3"}, {"vk-viewport", "800x600"}}},
      {"patch144",
       {{"vk-mode", "adaptive"}, {"vk-mu", "2"}, {"vk-eye", "2,3,6"}, {"vk-center", "5,5,0"}}},
  };
  // vk-corners: evaluated by the device's corner pass or by the host; the last pass moves the
  // control points after prepare() (update_control_points), so the corners must follow them.
  for (const char* corners : {"device", "host"})
    for (const bool moved : {false, true})
      for (const LevelCase& c : cases) {
        if (moved && std::string(c.scene) != "teapot") continue;
        SCOPED_TRACE(testing::Message()
                     << c.scene << " corners " << corners << (moved ? " moved" : ""));
        StrategyOptions options;
        options.extra = c.options;
        options.extra["vk-corners"] = corners;
        auto strategy = make_vk_ksquad(options);
        Scene scene = *make_builtin_scene(c.scene);
        strategy->prepare(scene, EvalRequest{Sampling{}, Precision::f32, false});
        // the camera is fitted once, in prepare(): to the unmoved scene
        const vk_ksquad::KsquadSettings settings = vk_ksquad::ksquad_settings(options);
        const std::array<float, 16> camera = vk_ksquad::scene_camera(scene, settings);
        if (moved) {
          for (Surface& s : scene.surfaces)
            for (auto& p : s.points) p[2] += 0.3 * p[0] + 0.1 * p[1] * p[1];
          strategy->update_control_points(scene);
        }
        strategy->evaluate();
        const std::vector<PatchLevels> device = ksquad_patch_levels(*strategy);
        const KsquadStatistics st = ksquad_statistics(*strategy);

        const double width = settings.viewport[0], height = settings.viewport[1], mu = settings.mu;
        std::set<std::tuple<int, int, int>> expected_quads, seen;
        for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
          const Surface& s = scene.surfaces[i];
          for (int su = s.degree_u; su < s.count_u; ++su)
            for (int sv = s.degree_v; sv < s.count_v; ++sv)
              if (s.knots_u[su] < s.knots_u[su + 1] && s.knots_v[sv] < s.knots_v[sv + 1])
                expected_quads.insert({static_cast<int>(i), su, sv});
        }
        std::size_t edges = 0, borderline = 0, mismatched = 0;
        double largest = 0;
        for (const PatchLevels& p : device) {
          seen.insert({p.surface, p.span_u, p.span_v});
          const Surface& s = scene.surfaces[p.surface];
          const SurfaceNet<double> net(s);
          Projected corner[2][2];
          for (int du = 0; du < 2; ++du)
            for (int dv = 0; dv < 2; ++dv)
              corner[du][dv] = project(
                  camera, surface_point(net, s.knots_u[p.span_u + du], s.knots_v[p.span_v + dv]),
                  width, height);
          // outer edges: u = x_i (corners (0,0)-(0,1)), v = y_j, u = x_i+1, v = y_j+1
          const Projected* ends[4][2] = {{&corner[0][0], &corner[0][1]},
                                         {&corner[0][0], &corner[1][0]},
                                         {&corner[1][0], &corner[1][1]},
                                         {&corner[0][1], &corner[1][1]}};
          for (int e = 0; e < 4; ++e) {
            double ratio = 0;
            const double want = eq3_level(*ends[e][0], *ends[e][1], mu, ratio);
            ++edges;
            largest = std::max(largest, want);
            // The device works in float (corners, matrix, distance): where dist / mu is within
            // float rounding of an integer, either neighbouring level is right.
            const bool near_integer =
                std::abs(ratio - std::round(ratio)) <= 1e-4 * std::max(1.0, ratio);
            if (p.wanted[e] != want) {
              if (near_integer && std::abs(p.wanted[e] - want) == 1) {
                ++borderline;
              } else {
                ++mismatched;
                ADD_FAILURE() << "surface " << p.surface << " KSQuad (" << p.span_u << ", "
                              << p.span_v << ") edge " << e << ": device " << p.wanted[e]
                              << ", eq. 3 " << want << " (dist / mu = " << ratio << ")";
              }
            }
          }
        }
        EXPECT_EQ(seen, expected_quads) << "one patch per KSQuad";
        EXPECT_EQ(mismatched, 0u);
        EXPECT_LE(borderline, edges / 100 + 1);
        EXPECT_EQ(st.evaluation_invocations, st.implied_vertices);
        EXPECT_GT(largest, 2) << "the camera should ask for more than one segment somewhere";
        EXPECT_EQ(strategy->device().details.at("vk_corners"), corners);
        std::cout << c.scene << " adaptive, " << corners << " corners" << (moved ? ", moved" : "")
                  << ": " << edges << " edges, levels up to " << largest << " (cap " << st.level_cap
                  << "), " << borderline << " borderline, " << st.evaluation_invocations
                  << " TES invocations\n";
      }
}

// eq. 3 read per edge (vk-eq3=edge) against its printed quantifiers (literal: one tau per KSQuad
// from its diagonal): the cracks the record counts (shared KSQuad edges whose two sides chose
// different levels) against those of the captured mesh -- an edge inside a surface whose two
// copies hold different numbers of vertices -- counted here from the vertices alone.
TEST(vk_ksquad_levels, LiteralEquation3CracksAreCounted) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  for (const char* scene_name : {"patch144", "torus"})  // teapot: no edge inside a surface
    for (const char* reading : {"edge", "literal"}) {
      SCOPED_TRACE(testing::Message() << scene_name << " " << reading);
      StrategyOptions options;
      options.extra = {{"vk-mode", "adaptive"}, {"vk-mu", "3"}, {"vk-eq3", reading}};
      auto strategy = make_vk_ksquad(options);
      const Scene scene = *make_builtin_scene(scene_name);
      strategy->prepare(scene, EvalRequest{Sampling{}, Precision::f32, false});
      strategy->evaluate();
      const KsquadStatistics st = ksquad_statistics(*strategy);
      std::map<std::tuple<int, int, float, float, float>, std::vector<std::size_t>> copies;
      for (const CapturedEdge& e : ksquad_captured_edges(*strategy))
        copies[{e.surface, e.direction, e.fixed, e.lo, e.hi}].push_back(e.vertices.size());
      std::size_t shared = 0, cracked = 0;
      for (const auto& [key, sizes] : copies) {
        if (sizes.size() != 2) continue;
        ++shared;
        cracked += sizes[0] != sizes[1];
      }
      EXPECT_EQ(st.shared_edges, shared);
      EXPECT_EQ(st.cracked_edges, cracked);
      if (std::string(reading) == "edge") {
        EXPECT_EQ(cracked, 0u);
      } else {
        EXPECT_GT(cracked, 0u);
      }
      std::cout << scene_name << " eq. 3 " << reading << ": " << shared << " shared edges, "
                << cracked << " cracked, levels up to " << st.max_level << ", "
                << st.evaluation_invocations << " TES invocations, " << st.tessellated_triangles
                << " triangles\n";
    }
}

// An unknown vk-mode is refused with the option, the value and every mapping the strategy has.
TEST(VkKsquadSettings, UnknownModeNamesEveryMapping) {
  StrategyOptions options;
  options.extra = {{"vk-mode", "sometimes"}};
  try {
    vk_ksquad::ksquad_settings(options);
    FAIL() << "vk-mode = sometimes accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "vk-ksquad option vk-mode = 'sometimes': must be uniform, adaptive, gs or "
                 "nonuniform");
  }
  for (const char* mode : {"uniform", "adaptive", "gs", "nonuniform"}) {
    options.extra = {{"vk-mode", mode}};
    EXPECT_STREQ(vk_ksquad::mapping_name(vk_ksquad::ksquad_settings(options).mapping), mode);
  }
}

}  // namespace
}  // namespace nurbs
