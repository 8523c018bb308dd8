// vk-ksquad's settings (StrategyOptions.extra) and camera, shared by every mapping: the camera
// is the one the adaptive test (003 eq. 3) projects with and the one render() draws with.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "reference/surface.h"
#include "strategies/strategy.h"

namespace nurbs::vk_ksquad {

// Patches per vkCmdDraw, bounded by the vertices the tessellator makes for them (see the .cpp).
inline constexpr std::uint64_t kDefaultVerticesPerDraw = 16384;
// Nonuniform mode's default vk-max-level: its KSDie records and vertex slots are stored per patch
// for the largest lattice, kNonuniformMaxLevel^2 KSDice of 25 slots.
inline constexpr int kNonuniformMaxLevel = 16;

// Settings (StrategyOptions.extra). vk-mode = uniform|adaptive|gs|nonuniform. Adaptive mode: vk-eye
// and vk-center = "x,y,z" (default: the scene's bounding sphere seen from (1, 0.8, 0.6) at 2.5
// radii), vk-fov = degrees (45), vk-viewport = "WxH" (1024x768), vk-mu = pixels (4),
// vk-corners = device|host (where the KSQuad corners of eq. 3 are evaluated; device),
// vk-max-level = N (the device's maxTessellationGenerationLevel), vk-pieces = N (2: a KSQuad's
// edge is cut into up to N patches, so levels up to N x vk-max-level). Every mode:
// vk-vertices-per-draw = N (kDefaultVerticesPerDraw; 0 = one draw per degree pair),
// vk-constants = device|host (where the per-span stair constants are computed; device).
// Nonuniform mode (vk-mode=nonuniform; adaptive's control stage and corner table, then a geometry
// stage): vk-epsilon = pixels (eq. 4's ε, 0.5), vk-eta = pixels (eq. 5's η, 4), vk-max-level
// (default 16: a KSQuad's lattice, KSDice stored per patch = its square), vk-pieces is 1.
// Adaptive and nonuniform: vk-eq3 = edge|literal (how eq. 3 is read, ksquad.tesc; edge),
// vk-thresholds = global|surface (μ, ε, η as given, or scaled per surface by
// surface_threshold_scales; global).
// vk-mode: how KSQuads become what the pipeline draws (003 §3-4).
enum class Mapping {
  uniform,     // one tessellation level per surface, from the requested sampling
  adaptive,    // levels from the camera (eq. 3, the control stage ksquad.tesc)
  gs,          // §4's GS-based mapping (ksquad.geom), span grid T <= 8
  nonuniform,  // adaptive's control stage and corner table, then a geometry stage (eqs. 4-5)
};
// "uniform", "adaptive", "gs", "nonuniform": the vk-mode value and the records' vk_mode detail.
const char* mapping_name(Mapping mapping);

struct KsquadSettings {
  Mapping mapping = Mapping::uniform;
  bool is(Mapping m) const { return mapping == m; }
  // adaptive and nonuniform: levels chosen from the camera by the control stage (eq. 3), with its
  // corner table, camera and thresholds; uniform and gs take theirs from the sampling
  bool camera_levels() const {
    return mapping == Mapping::adaptive || mapping == Mapping::nonuniform;
  }
  // gs and nonuniform draw through a geometry stage (the device needs geometryShader)
  bool geometry_stage() const { return mapping == Mapping::gs || mapping == Mapping::nonuniform; }
  double epsilon = 0.5, eta = 4;
  std::vector<double> eye, center, viewport;
  double fov = 45, mu = 4;
  int max_level = 0;
  // vk-eq3=literal: eq. 3's printed quantifiers (k < m and l < n) leave one corner pair, the
  // KSQuad's diagonal (x_i, y_j)-(x_i+1, y_j+1), so one tau for all four edges; edge (default):
  // each edge's level from its own two corners (ksquad.tesc), what makes neighbours agree
  bool eq3_literal = false;
  // vk-thresholds=surface: 003 §3.1's "thresholds ... precomputed for each surface"
  bool surface_thresholds = false;
  bool device_corners = true;  // adaptive: vk-corners = device (the corner pass) | host
  // Every mode: vk-constants = device (the per-span stair constants by ksquad_constants.comp,
  // once per prepare) | host (the C++ build of the same function, uploaded)
  bool device_constants = true;
  int pieces = 2;  // adaptive: patches per KSQuad and direction, levels up to pieces x max_level
  std::uint64_t vertices_per_draw = kDefaultVerticesPerDraw;
};

KsquadSettings ksquad_settings(const StrategyOptions& options);

// vk-vertices-per-draw (kDefaultVerticesPerDraw when absent; 0 = one draw per degree pair), the
// one setting vk-bezier shares; `strategy` names the strategy in errors.
std::uint64_t vertices_per_draw_option(const StrategyOptions& options, const char* strategy);

// Column-major perspective(fov_y) * look_at(eye, center, up = +z, or +y when looking along z).
std::array<float, 16> view_projection(const std::array<double, 3>& eye,
                                      const std::array<double, 3>& center, double fov_y_deg,
                                      double aspect, double near, double far);

// The camera of the settings: given, or fitted to the scene's control-point bounding sphere.
std::array<float, 16> scene_camera(const Scene& scene, const KsquadSettings& settings);

// vk-thresholds=surface: per surface, the factor its μ, ε and η are multiplied by -- its size on
// screen over the scene's, each the diagonal of the pixel bounding box of the projected control
// points (which bound the surface: strong convex hull, 003 §2), clamped to
// [kSmallestThresholdScale, 1]; 1 for a surface with a control point behind the eye (no finite
// size; the scene's box is that of the other surfaces). The given thresholds thus hold for a
// surface as large on screen as the whole scene, and every surface is approximated to the same
// fraction of its own size on screen (a quality level per surface, where the pixel thresholds alone
// give small surfaces few, coarse KSDice). Computed once per prepare with the camera (the paper's
// "precomputed").
inline constexpr double kSmallestThresholdScale = 1.0 / 64;
std::vector<double> surface_threshold_scales(const Scene& scene,
                                             const std::array<float, 16>& camera,
                                             const std::vector<double>& viewport);

}  // namespace nurbs::vk_ksquad
