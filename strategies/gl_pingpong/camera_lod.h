// 000 §3.2 continuous LOD, the half that needs no GL: the fly-in camera, its view-projection, and
// the rule that picks each surface's evaluation grid from its size on screen. Built in every build
// (the CLI and its tests use it without OpenGL); the frames themselves are drawn by gl-pingpong's
// LodRenderer (lod_renderer.h).
#pragma once

#include <array>
#include <optional>

#include "reference/surface.h"

namespace nurbs::gl_pingpong {

// A pinhole camera looking from `eye` at `target` into a width x height viewport.
struct Camera {
  Point3 eye{}, target{}, up{0, 0, 1};
  double fov_y_degrees = 45;
  int width = 640, height = 480;
  double near_plane = 0.01, far_plane = 100;
};

// Column-major (OpenGL) perspective x look-at, in float for the vertex shader.
std::array<float, 16> view_projection(const Camera& camera);
// Window coordinates (pixels, origin bottom-left) of p; nullopt when p is not beyond the near
// plane (its projection would be meaningless).
std::optional<std::array<double, 2>> project_to_pixels(const Camera& camera, const Point3& p);

struct LodRule {
  double pixels_per_sample = 4;  // one evaluated sample per this many pixels of projected length
  int min_samples = 4, max_samples = 256;  // per direction
};

struct LodResolution {
  int nu = 0, nv = 0;
  double u_pixels = 0, v_pixels = 0;  // the projected lengths the counts came from
};

// 000 §3.2 says only that the grid's "height and width" come from "the distance of the object
// from the eye point as well as the size of the object", continuously between a minimum and a
// maximum, different in u and v. Chosen here: the size on screen in each direction is the longest
// projected control polygon in that direction (u: max over columns j of the summed pixel lengths
// of P(i,j)-P(i+1,j); v likewise along rows), which bounds the projected curve's length (a
// B-spline lies in its control polygon's hull and is no longer than it for non-negative weights
// of equal size; a rough bound for others, and cheap: (n m) projections per surface); samples =
// ceil(pixels / pixels_per_sample) + 1, clamped to [min, max]. Off-screen parts are not clipped
// (a surface partly outside the viewport keeps its whole size), and a surface with a control
// point at or behind the near plane gets max in both directions.
LodResolution lod_resolution(const Surface& surface, const Camera& camera, const LodRule& rule);

// The fly-in: from `far_distance` to `near_distance` (in units of the bounding sphere's radius,
// geometric steps, so the size on screen grows steadily) along `direction` towards the centre of
// the sphere around every control point (the centre of their bounding box, radius half its
// diagonal). At the near end the eye is still outside the sphere, so no control point is behind it.
struct FlyIn {
  Point3 centre{};
  double radius = 1;
  Point3 direction{0.48, -0.64, 0.6};  // from the centre towards the eye (unit)
  double far_distance = 12, near_distance = 1.5;
};
FlyIn fly_in_of(const Scene& scene);
// Distance from the eye to the centre at frame f of `frames` (0: far; frames - 1: near).
double distance_at(const FlyIn& path, int frame, int frames);
Camera camera_at(const FlyIn& path, int frame, int frames, int width, int height);

}  // namespace nurbs::gl_pingpong
