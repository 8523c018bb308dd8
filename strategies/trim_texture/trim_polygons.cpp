#include "strategies/trim_texture/trim_polygons.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>

#include "reference/trim_crossings.h"
#include "strategies/strategy_options.h"

namespace nurbs::trim_texture {
namespace {

std::string_view option_text(const StrategyOptions& options, const char* key) {
  const auto it = options.extra.find(key);
  return it == options.extra.end() ? std::string_view{} : std::string_view(it->second);
}

[[noreturn]] void bad_option(std::string_view strategy, const char* key, std::string_view value,
                             std::string_view rule) {
  throw std::invalid_argument(
      fmt::format("{} option {} = '{}': must be {}", strategy, key, value, rule));
}

// Distance from p to the segment [a, b].
double segment_distance(const Point2& p, const Point2& a, const Point2& b) {
  const double dx = b[0] - a[0], dy = b[1] - a[1], length2 = dx * dx + dy * dy;
  double t = length2 > 0 ? ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy);
}

Point2 cartesian(const std::array<double, 3>& h) {
  return {h[0] / h[2], h[1] / h[2]};
}

// Appends the piece's start and, recursively, the starts of its halves until each chord is within
// `tolerance` of its stretch of curve. The test is on the control points: with positive weights
// (trim_validation requires them) a rational Bézier piece lies in the convex hull of its Cartesian
// control points, so when all of them are within `tolerance` of the chord, the curve is too.
void flatten(const TrimPiece<double>& piece, double tolerance, int depth,
             std::vector<Point2>& out) {
  const int n = piece.degree;
  const Point2 a = cartesian(piece.h[0]), b = cartesian(piece.h[n]);
  double error = 0;
  for (int i = 1; i < n; ++i)
    error = std::max(error, segment_distance(cartesian(piece.h[i]), a, b));
  // 40 halvings is 1e-12 of the piece's parameter range: beyond, float texels cannot tell.
  if (error <= tolerance || depth >= 40) {
    out.push_back(a);
    return;
  }
  TrimPiece<double> left, right;
  left.degree = right.degree = n;
  for (int c = 0; c < 3; ++c) {
    double coefficients[kMaxOrder], l[kMaxOrder], r[kMaxOrder];
    for (int i = 0; i <= n; ++i) coefficients[i] = piece.h[i][c];
    trim_detail::bernstein_halves(coefficients, n, l, r);
    for (int i = 0; i <= n; ++i) {
      left.h[i][c] = l[i];
      right.h[i][c] = r[i];
    }
  }
  flatten(left, tolerance, depth + 1, out);
  flatten(right, tolerance, depth + 1, out);
}

}  // namespace

Options parse_options(const StrategyOptions& options, std::string_view strategy) {
  Options out;
  if (const std::string_view r = option_text(options, "trim-resolution"); !r.empty()) {
    const int value = positive_option(options, "trim-resolution", strategy);
    if (value < kMinResolution || value > kMaxResolution)
      bad_option(strategy, "trim-resolution", r,
                 fmt::format("an integer from {} to {}", kMinResolution, kMaxResolution));
    out.resolution = value;
  }
  if (const std::string_view t = option_text(options, "trim-tolerance"); !t.empty()) {
    double value = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (ec != std::errc() || end != t.data() + t.size() || !std::isfinite(value) || !(value > 0) ||
        value > 0.1)
      bad_option(strategy, "trim-tolerance", t,
                 "a number in (0, 0.1] (a fraction of the surface's (u,v) domain diagonal)");
    out.tolerance = value;
  }
  return out;
}

std::vector<std::vector<Point2>> trim_polygons(const Trim& trim, double tolerance) {
  const TrimPieces<double> pieces = trim_pieces<double>(trim);
  std::vector<std::vector<Point2>> polygons;
  for (const std::vector<TrimPiece<double>>& loop : pieces.loops) {
    std::vector<Point2>& polygon = polygons.emplace_back();
    for (const TrimPiece<double>& piece : loop) flatten(piece, tolerance, 0, polygon);
  }
  return polygons;
}

double misclassification_distance(double du, double dv, int resolution, double tolerance_uv,
                                  int subpixel_bits) {
  return (0.5 + std::ldexp(1.0, -(subpixel_bits + 1))) *
             std::hypot(du / resolution, dv / resolution) +
         tolerance_uv;
}

}  // namespace nurbs::trim_texture
