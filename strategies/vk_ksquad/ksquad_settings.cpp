#include "strategies/vk_ksquad/ksquad_settings.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

#include "strategies/strategy_options.h"

namespace nurbs::vk_ksquad {

namespace {

std::vector<double> option_numbers(const StrategyOptions& options, const std::string& key,
                                   std::size_t count, char separator) {
  const auto it = options.extra.find(key);
  if (it == options.extra.end() || it->second.empty()) return {};
  std::vector<double> values;
  std::size_t start = 0;
  const std::string& text = it->second;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find(separator, start), text.size());
    const std::string item = text.substr(start, end - start);
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != item.size() || !std::isfinite(value))
      throw std::invalid_argument(
          fmt::format("vk-ksquad option {} = '{}': expected {} numbers", key, text, count));
    values.push_back(value);
    start = end + 1;
  }
  if (values.size() != count)
    throw std::invalid_argument(
        fmt::format("vk-ksquad option {} = '{}': expected {} numbers", key, text, count));
  return values;
}

}  // namespace

std::array<float, 16> view_projection(const std::array<double, 3>& eye,
                                      const std::array<double, 3>& center, double fov_y_deg,
                                      double aspect, double near, double far) {
  using V = std::array<double, 3>;
  const auto sub = [](V a, V b) { return V{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  const auto cross = [](V a, V b) {
    return V{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const auto dot = [](V a, V b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; };
  const auto unit = [&](V a) {
    const double n = std::sqrt(dot(a, a));
    return V{a[0] / n, a[1] / n, a[2] / n};
  };
  const V f = unit(sub(center, eye));
  const V up = std::abs(f[2]) > 0.99 ? V{0, 1, 0} : V{0, 0, 1};
  const V r = unit(cross(f, up));
  const V u = cross(r, f);
  const double t = 1.0 / std::tan(fov_y_deg * M_PI / 360.0);
  // Vulkan depth in [0, 1] between near and far (render() only)
  const double a = far / (far - near), b = -far * near / (far - near);
  // rows of the product (w = distance along f; x, y, w are all the adaptive test uses)
  const double rows[4][4] = {
      {t / aspect * r[0], t / aspect * r[1], t / aspect * r[2], -t / aspect * dot(r, eye)},
      // y flipped: Vulkan's clip-space +y points down the framebuffer, so without the flip
      // world-up lands at the bottom of render()'s image
      {-t * u[0], -t * u[1], -t * u[2], t * dot(u, eye)},
      {a * f[0], a * f[1], a * f[2], -a * dot(f, eye) + b},
      {f[0], f[1], f[2], -dot(f, eye)}};
  std::array<float, 16> m{};
  for (int c = 0; c < 4; ++c)
    for (int k = 0; k < 4; ++k) m[4 * c + k] = static_cast<float>(rows[k][c]);
  return m;
}

// kDefaultVerticesPerDraw (ksquad_settings.h):
// patches per vkCmdDraw are bounded by the vertices the tessellator makes for them. Not in the
// paper, which draws each KSQuad set at once: on lavapipe (Mesa 22.3) one draw's cost grows with
// the square of its vertex count -- perf puts the time in a loop of libvulkan_lvp.so that stores
// 0xffff into a 16-bit field of every vertex (by its shape, the draw module resetting vertex ids
// at each internal flush), and patch144 at 2048x2048 (4M vertices) in one draw took minutes per
// evaluation. Bounded draws keep it linear; on a GPU they are a handful of
// draw calls more. Measured on lavapipe, patch144 at 1024x1024: 14 s per evaluation in one draw,
// 1.2 s with 1024 to 16384 vertices per draw, 2.9 s with 262144.
namespace {
constexpr Mapping kMappings[] = {Mapping::uniform, Mapping::adaptive, Mapping::gs,
                                 Mapping::nonuniform};
}  // namespace

namespace {
// "uniform, adaptive, gs or nonuniform", read off kMappings so that the error names every mapping.
std::string mapping_choices() {
  std::string out;
  const std::size_t n = std::size(kMappings);
  for (std::size_t k = 0; k < n; ++k)
    out += std::string(k == 0 ? "" : k + 1 == n ? " or " : ", ") + mapping_name(kMappings[k]);
  return out;
}
}  // namespace

const char* mapping_name(Mapping mapping) {
  switch (mapping) {
    case Mapping::uniform:
      return "uniform";
    case Mapping::adaptive:
      return "adaptive";
    case Mapping::gs:
      return "gs";
    case Mapping::nonuniform:
      return "nonuniform";
  }
  return "?";
}

KsquadSettings ksquad_settings(const StrategyOptions& options) {
  KsquadSettings a;
  if (auto it = options.extra.find("vk-mode"); it != options.extra.end() && !it->second.empty()) {
    const auto known = std::find_if(std::begin(kMappings), std::end(kMappings),
                                    [&](Mapping m) { return it->second == mapping_name(m); });
    if (known == std::end(kMappings))
      throw std::invalid_argument("vk-ksquad option vk-mode = '" + it->second + "': must be " +
                                  mapping_choices());
    a.mapping = *known;
  }
  const auto choice = [&](const char* key, const char* first, const char* second) {
    const auto it = options.extra.find(key);
    if (it == options.extra.end() || it->second.empty()) return false;
    if (it->second != first && it->second != second)
      throw std::invalid_argument(fmt::format("vk-ksquad option {} = '{}': must be {} or {}", key,
                                              it->second, first, second));
    return it->second == second;
  };
  a.eq3_literal = choice("vk-eq3", "edge", "literal");
  a.surface_thresholds = choice("vk-thresholds", "global", "surface");
  for (const char* key : {"vk-eq3", "vk-thresholds"})
    if (!a.camera_levels() && options.extra.count(key))
      throw std::invalid_argument(fmt::format(
          "vk-ksquad: {} applies to vk-mode=adaptive and vk-mode=nonuniform only", key));
  if (auto it = options.extra.find("vk-corners");
      it != options.extra.end() && !it->second.empty()) {
    if (it->second != "device" && it->second != "host")
      throw std::invalid_argument("vk-ksquad option vk-corners = '" + it->second +
                                  "': must be device or host");
    a.device_corners = it->second == "device";
  }
  if (auto it = options.extra.find("vk-constants");
      it != options.extra.end() && !it->second.empty()) {
    if (it->second != "device" && it->second != "host")
      throw std::invalid_argument("vk-ksquad option vk-constants = '" + it->second +
                                  "': must be device or host");
    a.device_constants = it->second == "device";
  }
  a.eye = option_numbers(options, "vk-eye", 3, ',');
  a.center = option_numbers(options, "vk-center", 3, ',');
  a.viewport = option_numbers(options, "vk-viewport", 2, 'x');
  if (a.viewport.empty()) a.viewport = {1024, 768};
  if (auto fov = option_numbers(options, "vk-fov", 1, ','); !fov.empty()) a.fov = fov[0];
  if (auto mu = option_numbers(options, "vk-mu", 1, ','); !mu.empty()) a.mu = mu[0];
  if (a.mu <= 0 || a.fov <= 0 || a.fov >= 180 || a.viewport[0] < 1 || a.viewport[1] < 1)
    throw std::invalid_argument("vk-ksquad: vk-mu, vk-fov and vk-viewport must be positive");
  if (auto e = option_numbers(options, "vk-epsilon", 1, ','); !e.empty()) a.epsilon = e[0];
  if (auto e = option_numbers(options, "vk-eta", 1, ','); !e.empty()) a.eta = e[0];
  if (!(a.epsilon > 0) || !(a.eta > 0))
    throw std::invalid_argument("vk-ksquad: vk-epsilon and vk-eta must be positive");
  a.max_level = positive_option(options, "vk-max-level", "vk-ksquad");
  if (const int pieces = positive_option(options, "vk-pieces", "vk-ksquad"); pieces > 0)
    a.pieces = pieces;
  if (a.mapping == Mapping::nonuniform) {
    // one patch per KSQuad: its lattice is capped, not cut (ksquad.tesc's nonuniform branch)
    if (options.extra.count("vk-pieces"))
      throw std::invalid_argument("vk-ksquad: vk-pieces does not apply to vk-mode=nonuniform");
    a.pieces = 1;
    if (a.max_level == 0) a.max_level = kNonuniformMaxLevel;
  }
  a.vertices_per_draw = vertices_per_draw_option(options, "vk-ksquad");
  return a;
}

std::uint64_t vertices_per_draw_option(const StrategyOptions& options, const char* strategy) {
  const auto it = options.extra.find("vk-vertices-per-draw");
  if (it == options.extra.end()) return kDefaultVerticesPerDraw;
  return it->second == "0" ? 0
                           : static_cast<std::uint64_t>(
                                 positive_option(options, "vk-vertices-per-draw", strategy));
}

std::array<float, 16> scene_camera(const Scene& scene, const KsquadSettings& settings) {
  std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  for (const Surface& s : scene.surfaces)
    for (const auto& p : s.points)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], p[c]);
        hi[c] = std::max(hi[c], p[c]);
      }
  std::array<double, 3> center{}, eye{};
  const double radius =
      0.5 * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
  const double dir[3] = {1 / std::sqrt(2.0), 0.8 / std::sqrt(2.0), 0.6 / std::sqrt(2.0)};
  for (int c = 0; c < 3; ++c) {
    center[c] = settings.center.empty() ? 0.5 * (lo[c] + hi[c]) : settings.center[c];
    eye[c] =
        settings.eye.empty() ? center[c] + 2.5 * std::max(radius, 1e-30) * dir[c] : settings.eye[c];
  }
  double distance = 0;
  for (int c = 0; c < 3; ++c)
    distance += (eye[c] - 0.5 * (lo[c] + hi[c])) * (eye[c] - 0.5 * (lo[c] + hi[c]));
  distance = std::sqrt(distance);
  const double far = distance + 1.5 * radius + 1e-30;
  const double near = std::max(distance - 1.5 * radius, 1e-4 * far);
  return view_projection(eye, center, settings.fov, settings.viewport[0] / settings.viewport[1],
                         near, far);
}

std::vector<double> surface_threshold_scales(const Scene& scene,
                                             const std::array<float, 16>& camera,
                                             const std::vector<double>& viewport) {
  struct Box {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    bool behind = false;
    double diagonal() const {
      return behind || lo[0] > hi[0] ? 0 : std::hypot(hi[0] - lo[0], hi[1] - lo[1]);
    }
  };
  Box all;
  std::vector<Box> boxes(scene.surfaces.size());
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
    for (const auto& p : scene.surfaces[i].points) {
      double c[4];
      for (int r = 0; r < 4; ++r)
        c[r] = camera[r] * p[0] + camera[4 + r] * p[1] + camera[8 + r] * p[2] + camera[12 + r];
      if (!(c[3] > 0)) {
        boxes[i].behind = true;
        continue;
      }
      const double px[2] = {c[0] / c[3] * 0.5 * viewport[0], c[1] / c[3] * 0.5 * viewport[1]};
      for (int k = 0; k < 2; ++k) {
        boxes[i].lo[k] = std::min(boxes[i].lo[k], px[k]);
        boxes[i].hi[k] = std::max(boxes[i].hi[k], px[k]);
      }
    }
  // the scene's box: of the surfaces wholly in front of the eye
  for (const Box& b : boxes)
    if (!b.behind)
      for (int k = 0; k < 2; ++k) {
        all.lo[k] = std::min(all.lo[k], b.lo[k]);
        all.hi[k] = std::max(all.hi[k], b.hi[k]);
      }
  std::vector<double> scales(scene.surfaces.size(), 1.0);
  const double whole = all.diagonal();
  for (std::size_t i = 0; i < boxes.size(); ++i)
    if (!boxes[i].behind && whole > 0)
      scales[i] = std::clamp(boxes[i].diagonal() / whole, kSmallestThresholdScale, 1.0);
  return scales;
}

}  // namespace nurbs::vk_ksquad
