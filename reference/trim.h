// Trimming loops of a surface (nurbs-scene/2, the real-CAD issue): 2D NURBS curves in the
// surface's own (u, v) space, outer loop first. A (u, v) is inside when a ray from it crosses the
// loops an odd number of times (000 §4's odd/even trim texture: orientation-free, so loops need no
// consistent direction and nested holes work).
#pragma once

#include <array>
#include <string>
#include <vector>

namespace nurbs {

using Point2 = std::array<double, 2>;

// A 2D NURBS curve in the surface's (u, v) space: Cartesian points (not pre-multiplied by the
// weight); knot count = points + degree + 1; the curve is its whole clamped or unclamped domain
// [knots[degree], knots[points]].
struct TrimCurve {
  int degree = 0;
  std::vector<double> knots;
  std::vector<Point2> points;
  std::vector<double> weights;  // same order; all 1 when the file gave none
};

// Curves in order, each one's end meeting the next one's start (and the last the first) within
// Trim::tolerance.
struct TrimLoop {
  std::vector<TrimCurve> curves;
};

inline constexpr const char* kTrimRuleEvenOdd = "even-odd";

struct Trim {
  std::string rule = kTrimRuleEvenOdd;  // the only rule: even-odd
  // Largest gap allowed between consecutive curve ends, and how far a curve may leave the
  // surface's domain, in (u, v) units.
  double tolerance = 1e-9;
  std::vector<TrimLoop> loops;
};

// Bounds that keep an absurd file from making us allocate (checked before allocation).
inline constexpr std::size_t kMaxTrimLoops = 1 << 16;
inline constexpr std::size_t kMaxTrimCurvesPerLoop = 1 << 16;
inline constexpr std::size_t kMaxTrimPointsPerCurve = 1 << 20;

}  // namespace nurbs
