#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "reference/surface_checker.h"
#include "reference/tspline.h"
#include "strategies/strategy.h"

namespace nurbs {
namespace {

// A strategy converts the scene's doubles to its precision T (float for --precision f32) and
// forms the homogeneous coordinates (w*x, w*y, w*z, w) of every control point (and (w*u, w*v, w)
// of a trim curve's). The rule: every coordinate, knot and w*coordinate is finite in T, and every
// weight is at least T's smallest normal number (a subnormal weight has lost its relative
// precision, and 1e-320 becomes 0 in float: a division by zero). The sums of those terms need no
// check of their own: the basis functions are non-negative and sum to one, so each homogeneous sum
// is a convex combination of its terms, no larger than the largest, and dividing by the weight
// sum gives a point of the control points' convex hull. Tiny coordinates are allowed: flushing
// them to 0 is an absolute error below T's smallest normal. Derivatives (normals) scale
// differences of terms by degree / knot span, which no rule on the values alone bounds; such an
// overflow is measured, not refused. In double only the products and subnormal weights can
// fail, since validation already requires finite doubles.
template <typename T>
class PrecisionRange {
 public:
  PrecisionRange(const Surface& s, std::size_t index) : s_(s), index_(index) {}

  // Control points (3D or a trim curve's 2D) with their weights.
  template <typename Point>
  std::optional<std::string> check(const std::string& field, const std::vector<Point>& points,
                                   const std::string& weights_field,
                                   const std::vector<double>& weights) const {
    for (std::size_t k = 0; k < points.size(); ++k) {
      const double w = weights[k];
      if (!(w >= kMin))
        return refuse(weights_field, std::to_string(k), format_number(w),
                      fmt::format("below {}'s smallest normal number {} (it would round to 0 or "
                                  "lose its precision)",
                                  kName, format_number(kMin)));
      if (!(w <= kMax)) return too_large(weights_field, std::to_string(k), w);
      for (std::size_t c = 0; c < points[k].size(); ++c) {
        const double x = points[k][c];
        // An overflow to infinity in double fails the comparison as well.
        if (std::fabs(x) <= kMax && std::fabs(w * x) <= kMax) continue;
        const std::string index = fmt::format("{}][{}", k, c);
        if (!(std::fabs(x) <= kMax)) return too_large(field, index, x);
        return refuse(field, index, format_number(x),
                      fmt::format("times its weight {} is {:g}, beyond {}'s largest number {}",
                                  format_number(w), static_cast<long double>(w) * x, kName,
                                  format_number(kMax)));
      }
    }
    return std::nullopt;
  }

  std::optional<std::string> check_knots(const std::string& field,
                                         const std::vector<double>& knots) const {
    for (std::size_t k = 0; k < knots.size(); ++k)
      if (!(std::fabs(knots[k]) <= kMax)) return too_large(field, std::to_string(k), knots[k]);
    return std::nullopt;
  }

 private:
  static constexpr double kMax = std::numeric_limits<T>::max();
  static constexpr double kMin = std::numeric_limits<T>::min();
  static constexpr const char* kName = sizeof(T) == sizeof(float) ? "float32" : "float64";

  std::string refuse(const std::string& field, const std::string& index, const std::string& value,
                     const std::string& rule) const {
    return fmt::format("surface '{}' (#{}): {}[{}] = {}: {}{}", s_.name, index_, field, index,
                       value, rule,
                       sizeof(T) == sizeof(float) ? "; evaluate it with --precision f64" : "");
  }
  std::string too_large(const std::string& field, const std::string& index, double value) const {
    return refuse(field, index, format_number(value),
                  fmt::format("beyond {}'s largest number {}", kName, format_number(kMax)));
  }

  const Surface& s_;
  std::size_t index_;
};

template <typename T>
std::optional<std::string> range_violation(const Surface& s, std::size_t index) {
  const PrecisionRange<T> range(s, index);
  if (s.is_tspline()) {
    // Local knot vectors, one after another (point k's at k*(degree+2)).
    if (auto v = range.check_knots("knots_u", s.tspline->knots_u)) return v;
    if (auto v = range.check_knots("knots_v", s.tspline->knots_v)) return v;
  } else {
    if (auto v = range.check_knots("knots_u", s.knots_u)) return v;
    if (auto v = range.check_knots("knots_v", s.knots_v)) return v;
  }
  if (auto v = range.check("points", s.control_points(), "weights", s.control_weights())) return v;
  if (!s.trim) return std::nullopt;
  for (std::size_t l = 0; l < s.trim->loops.size(); ++l)
    for (std::size_t c = 0; c < s.trim->loops[l].curves.size(); ++c) {
      const TrimCurve& curve = s.trim->loops[l].curves[c];
      const std::string path = trim_curve_path(l, c);
      if (auto v = range.check_knots(path + ".knots", curve.knots)) return v;
      if (auto v = range.check(path + ".points", curve.points, path + ".weights", curve.weights))
        return v;
    }
  return std::nullopt;
}

}  // namespace

std::string sampling_mode_name(SamplingMode mode) {
  switch (mode) {
    case SamplingMode::grid:
      return "grid";
    case SamplingMode::span_grid:
      return "span_grid";
    case SamplingMode::explicit_list:
      break;
  }
  return "explicit";
}

namespace {
constexpr std::string_view kNurbsOnly = "the strategy evaluates NURBS only";
constexpr std::string_view kTsplinesOnly = "the strategy evaluates T-splines only";
}  // namespace

bool is_kind_refusal(std::string_view reason) {
  return reason.find(kNurbsOnly) != std::string_view::npos ||
         reason.find(kTsplinesOnly) != std::string_view::npos;
}

std::optional<std::string> refusal_reason(const Capabilities& caps, const Scene& scene,
                                          const EvalRequest& request) {
  if (!caps.supports(request.precision))
    return fmt::format("precision {} not supported", to_string(request.precision));
  if (!caps.sampling.supports(request.sampling.mode))
    return fmt::format("sampling mode {} not supported", sampling_mode_name(request.sampling.mode));
  if (request.normals && !caps.normals) return std::string("normals not supported");
  for (const Surface& s : scene.surfaces) {
    if (s.is_tspline() && !caps.tspline)
      return fmt::format("surface '{}' is a T-spline, {}", s.name, kNurbsOnly);
    if (!s.is_tspline() && caps.tspline_only)
      return fmt::format("surface '{}' is a NURBS surface, {}", s.name, kTsplinesOnly);
    if (std::max(s.degree_u, s.degree_v) > caps.max_degree)
      return fmt::format("surface '{}' has degree {}x{}, the strategy supports at most {}", s.name,
                         s.degree_u, s.degree_v, caps.max_degree);
    if (!caps.rational && s.is_rational())
      return fmt::format("surface '{}' is rational, the strategy is polynomial only", s.name);
  }
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
    if (auto reason = request.precision == Precision::f32
                          ? range_violation<float>(scene.surfaces[i], i)
                          : range_violation<double>(scene.surfaces[i], i))
      return reason;
  return std::nullopt;
}

void refuse_unsupported(std::string_view strategy, const Capabilities& caps, const Scene& scene,
                        const EvalRequest& request) {
  if (auto reason = refusal_reason(caps, scene, request))
    throw RefusedError(fmt::format("{}: {}", strategy, *reason));
}

void Strategy::prepare(const Scene& scene, const EvalRequest& request) {
  refuse_unsupported(name(), capabilities(), scene, request);
  prepare_checked(scene, request);
}

}  // namespace nurbs
