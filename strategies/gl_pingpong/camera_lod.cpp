#include "strategies/gl_pingpong/camera_lod.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace nurbs::gl_pingpong {
namespace {

Point3 sub(const Point3& a, const Point3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
double dot(const Point3& a, const Point3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
Point3 cross(const Point3& a, const Point3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
Point3 unit(const Point3& a) {
  const double n = std::sqrt(dot(a, a));
  return {a[0] / n, a[1] / n, a[2] / n};
}

// The camera's frame: right, true up, and the viewing direction (eye towards target).
struct Basis {
  Point3 right, up, forward;
};
Basis basis_of(const Camera& c) {
  const Point3 forward = unit(sub(c.target, c.eye));
  const Point3 right = unit(cross(forward, c.up));
  return {right, cross(right, forward), forward};
}

// Clip coordinates (x, y, z, w) of p, in double.
std::array<double, 4> clip_of(const Camera& c, const Basis& b, const Point3& p) {
  const Point3 d = sub(p, c.eye);
  const double x = dot(d, b.right), y = dot(d, b.up), depth = dot(d, b.forward);
  const double f = 1 / std::tan(c.fov_y_degrees * std::numbers::pi / 360);
  const double aspect = static_cast<double>(c.width) / c.height;
  const double n = c.near_plane, fa = c.far_plane;
  return {f / aspect * x, f * y, (fa + n) / (fa - n) * depth - 2 * fa * n / (fa - n), depth};
}

}  // namespace

std::array<float, 16> view_projection(const Camera& c) {
  // Column k of the matrix is the clip coordinates of the k-th unit vector minus those of the
  // origin (k < 3), and column 3 those of the origin: clip_of is affine in p.
  const Basis b = basis_of(c);
  const std::array<double, 4> origin = clip_of(c, b, {0, 0, 0});
  std::array<float, 16> m{};
  for (int k = 0; k < 3; ++k) {
    Point3 e{0, 0, 0};
    e[static_cast<std::size_t>(k)] = 1;
    const std::array<double, 4> column = clip_of(c, b, e);
    for (int r = 0; r < 4; ++r)
      m[static_cast<std::size_t>(k * 4 + r)] = static_cast<float>(column[r] - origin[r]);
  }
  for (int r = 0; r < 4; ++r) m[static_cast<std::size_t>(12 + r)] = static_cast<float>(origin[r]);
  return m;
}

std::optional<std::array<double, 2>> project_to_pixels(const Camera& c, const Point3& p) {
  const std::array<double, 4> clip = clip_of(c, basis_of(c), p);
  if (!(clip[3] > c.near_plane)) return std::nullopt;
  return std::array<double, 2>{(clip[0] / clip[3] + 1) * 0.5 * c.width,
                               (clip[1] / clip[3] + 1) * 0.5 * c.height};
}

LodResolution lod_resolution(const Surface& s, const Camera& c, const LodRule& rule) {
  std::vector<std::array<double, 2>> pixels(s.points.size());
  bool behind = false;
  for (std::size_t k = 0; k < s.points.size() && !behind; ++k) {
    const auto p = project_to_pixels(c, s.points[k]);
    if (p)
      pixels[k] = *p;
    else
      behind = true;
  }
  LodResolution r;
  if (behind) {
    r.nu = r.nv = rule.max_samples;
    r.u_pixels = r.v_pixels = std::numeric_limits<double>::infinity();
    return r;
  }
  auto length = [&](int i0, int j0, int i1, int j1) {
    const auto& a = pixels[static_cast<std::size_t>(i0) * s.count_v + j0];
    const auto& b = pixels[static_cast<std::size_t>(i1) * s.count_v + j1];
    return std::hypot(b[0] - a[0], b[1] - a[1]);
  };
  for (int j = 0; j < s.count_v; ++j) {
    double sum = 0;
    for (int i = 0; i + 1 < s.count_u; ++i) sum += length(i, j, i + 1, j);
    r.u_pixels = std::max(r.u_pixels, sum);
  }
  for (int i = 0; i < s.count_u; ++i) {
    double sum = 0;
    for (int j = 0; j + 1 < s.count_v; ++j) sum += length(i, j, i, j + 1);
    r.v_pixels = std::max(r.v_pixels, sum);
  }
  auto samples = [&](double px) {
    const double n = std::ceil(px / rule.pixels_per_sample) + 1;
    return static_cast<int>(std::clamp(n, double(rule.min_samples), double(rule.max_samples)));
  };
  r.nu = samples(r.u_pixels);
  r.nv = samples(r.v_pixels);
  return r;
}

FlyIn fly_in_of(const Scene& scene) {
  Point3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Surface& s : scene.surfaces)
    for (const Point3& p : s.control_points())
      for (std::size_t k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
  FlyIn path;
  path.centre = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  path.radius = std::max(std::sqrt(dot(sub(hi, lo), sub(hi, lo))) / 2, 1e-30);
  return path;
}

double distance_at(const FlyIn& path, int frame, int frames) {
  const double t = frames > 1 ? static_cast<double>(frame) / (frames - 1) : 0;
  return path.radius * path.far_distance * std::pow(path.near_distance / path.far_distance, t);
}

Camera camera_at(const FlyIn& path, int frame, int frames, int width, int height) {
  const double d = distance_at(path, frame, frames);
  Camera c;
  c.target = path.centre;
  c.eye = {path.centre[0] + d * path.direction[0], path.centre[1] + d * path.direction[1],
           path.centre[2] + d * path.direction[2]};
  c.width = width;
  c.height = height;
  // Everything lies within the sphere: between d - r and d + r from the eye.
  c.near_plane = std::max(d - path.radius, 0.0) * 0.5 + path.radius * 1e-3;
  c.far_plane = d + 2 * path.radius;
  return c;
}

}  // namespace nurbs::gl_pingpong
