// 000 §4 (Krishnamurthy et al. 2007), the host half of the trim texture: "the trim curves are
// evaluated and converted to piecewise linear segments", then rasterized by odd/even blending
// (trim_texture.h). This half is GL-free: the options, the polygons, and the distance within which
// the texture can disagree with the exact classification (the bound the tests and the report use).
#pragma once

#include <string_view>
#include <vector>

#include "reference/trim.h"
#include "strategies/strategy.h"

namespace nurbs::trim_texture {

// The paper gives neither a texture size nor a tessellation tolerance; these are ours.
inline constexpr int kDefaultResolution = 1024;
inline constexpr int kMinResolution = 64;
inline constexpr int kMaxResolution = 4096;
// A fraction of the surface's (u, v) domain diagonal, like --trim-band, so one value means the
// same on every surface whatever its parametrization.
inline constexpr double kDefaultTolerance = 1e-5;

struct Options {
  int resolution = kDefaultResolution;   // the texture is resolution x resolution texels
  double tolerance = kDefaultTolerance;  // chordal tolerance, fraction of the domain diagonal
};

// "trim-resolution" (an integer in [64, 4096]) and "trim-tolerance" (a number in (0, 0.1]) from
// StrategyOptions.extra; throws std::invalid_argument naming the strategy, option and value.
Options parse_options(const StrategyOptions& options, std::string_view strategy);

// Each loop as a closed polygon (the closing edge from the last vertex to the first is implied),
// every edge within `tolerance` ((u, v) units) of the curve stretch it replaces. A gap between
// consecutive curves (allowed up to Trim::tolerance) becomes a straight edge, as the exact
// classifier closes it (reference/trim_crossings.h).
std::vector<std::vector<Point2>> trim_polygons(const Trim& trim, double tolerance);

// How far from the exact trim boundary a sample must lie for the texture to classify it
// correctly, d = (1/2 + 2^-(s+1)) * texel diagonal + tolerance_uv: half a texel diagonal (the
// sample reads the nearest texel centre, whose polygon parity rasterization decided), the
// rasterizer's snapping of polygon vertices to 2^-s of a texel (s = GL_SUBPIXEL_BITS: a vertex
// moves at most 2^-(s+1) of a texel per axis, so an edge at most 2^-(s+1) of the diagonal), and
// the chordal tolerance (a point whose parity differs between polygon and curves is within the
// tolerance of the curves). `du`, `dv`: the domain's extent, in (u, v) units like tolerance_uv.
// The one definition of d: the trim-texture test asserts it per sample, docs/trimming.md and the
// report's trim_texture_resolution note state it.
double misclassification_distance(double du, double dv, int resolution, double tolerance_uv,
                                  int subpixel_bits);

}  // namespace nurbs::trim_texture
