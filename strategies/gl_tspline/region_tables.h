// gl-tspline, CPU side (001 "T-splines GPU evaluation", step 1, and Fig 7): everything the passes
// read, as flat arrays laid out for textures. GL-free, so the tables are unit-tested everywhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "reference/sampling.h"
#include "reference/tspline.h"

namespace nurbs::gl_tspline {

// Per-point and per-region arrays are "linear" textures: element i at texel
// (i % kLinearWidth, i / kLinearWidth). 1024 is GL 3.3's smallest allowed GL_MAX_TEXTURE_SIZE, so
// the width fits every conforming driver; the shaders get it as LINEAR_WIDTH.
inline constexpr int kLinearWidth = 1024;

// Rows of a linear texture of `elements` texels (at least 1).
int linear_rows(std::size_t elements);

struct RegionTables {
  int degree_u = 0, degree_v = 0;
  std::size_t points = 0, regions = 0, entries = 0;
  // Padded to whole rows of kLinearWidth texels (zeros).
  std::vector<float> homogeneous;  // RGBA per control point: w x, w y, w z, w
  std::vector<float> knots_u;      // R per knot: point k's local vector at k * (degree_u + 2)
  std::vector<float> knots_v;
  // R per region + 1: CSR offsets into `active`; region (cu, cv) is cu * cells_v + cv, as in
  // TSplineInfluence.
  std::vector<std::int32_t> offsets;
  // RGBA per active entry: control point, span of its local u vector holding the region, the
  // same in v, 0. 001 stores the point indices only; the spans are added (found in double with
  // the reference's local_span at the region's lower-left corner) so that the GPU uses the
  // polynomial piece the reference uses, even where rounding the parameter to float moves it
  // across a knot line or onto a support's end (where a clamped end function jumps).
  std::vector<std::int32_t> active;
  // The most control points any region has: the number of terms a sample can need, hence
  // the passes (001: "the number of control points n is different for each evaluation point").
  int max_active = 0;
};

RegionTables make_region_tables(const TSplineSurface& surface, const TSplineInfluence& index);

// RegionTables::homogeneous alone: what update_control_points re-uploads when the points move.
std::vector<float> homogeneous_points(const TSplineSurface& surface);

// Per sample, one texel per fragment of the passes: (u, v) in float and its region, found by the
// influence index's binary searches (001: "O(log n) ... using binary search"). Sample k at texel
// (k % width, k / width); the last row is padded with copies of sample 0.
struct SampleTable {
  int width = 0, height = 0;
  std::size_t count = 0;
  std::vector<float> uv;              // RG
  std::vector<std::int32_t> regions;  // R
};

SampleTable make_sample_table(const TSplineInfluence& index, const SurfaceSamples& samples);

// 001's split: each accumulation pass adds `points_per_pass` active points of every sample's
// region, so ceil(max_active / points_per_pass) passes cover the largest region; one divide pass
// follows.
int accumulation_passes(int max_active, int points_per_pass);

}  // namespace nurbs::gl_tspline
