#include "reference/validation.h"

#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "reference/error_text.h"
#include "reference/surface_checker.h"
#include "reference/tspline.h"

namespace nurbs {

ValidationError::ValidationError(std::string origin, std::string surface, int surface_index,
                                 std::string field, std::string index, std::string value,
                                 std::string rule)
    // Every part may come from the file (a name, a key): escaped, so the message stays one line.
    : InputError(fmt::format("{}: surface '{}' (#{}): {}{} = {}: {}", printable(origin),
                             printable(surface, kQuotedValueBytes), surface_index,
                             printable(field, kQuotedValueBytes),
                             index.empty()           ? ""
                             : index == kLengthIndex ? " length"
                                                     : fmt::format("[{}]", printable(index)),
                             printable(value, kQuotedValueBytes), printable(rule))),
      origin_(std::move(origin)),
      surface_(std::move(surface)),
      surface_index_(surface_index),
      field_(std::move(field)),
      index_(std::move(index)),
      value_(std::move(value)),
      rule_(std::move(rule)) {}

std::string format_number(double value) {
  return fmt::format("{}", value);
}

void SurfaceChecker::fail(std::string field, std::string index, std::string value,
                          std::string rule) const {
  throw ValidationError(std::string(origin_), surface_.name, surface_index_, std::move(field),
                        std::move(index), std::move(value), std::move(rule));
}

void SurfaceChecker::check_degree(const std::string& field, int degree) const {
  if (degree < 1 || degree > kMaxDegree)
    fail(field, "", std::to_string(degree), fmt::format("degree must be in 1..{}", kMaxDegree));
}

void SurfaceChecker::check_count(const std::string& field, const std::string& index,
                                 std::int64_t count, int degree, std::int64_t max_count) const {
  if (count < degree + 1 || count > max_count)
    fail(field, index, std::to_string(count),
         fmt::format("need degree+1 = {} to {} control points", degree + 1, max_count));
}

void SurfaceChecker::check_knots(const std::string& field, const std::vector<double>& knots,
                                 int degree, int count) const {
  const std::size_t expected = static_cast<std::size_t>(count) + degree + 1;
  if (knots.size() != expected)
    fail(field, kLengthIndex, std::to_string(knots.size()),
         fmt::format("knot count must be count + degree + 1 = {}", expected));
  for (std::size_t k = 0; k < knots.size(); ++k) {
    if (!std::isfinite(knots[k]))
      fail(field, std::to_string(k), format_number(knots[k]), "knots must be finite");
    if (k > 0 && knots[k] < knots[k - 1])
      fail(field, std::to_string(k), format_number(knots[k]),
           fmt::format("knots must be non-decreasing (previous is {})",
                       format_number(knots[k - 1])));
  }
  // A run of equal knots touching either end may have multiplicity degree+1 (clamped ends);
  // any other run at most degree, or the surface would be discontinuous there.
  for (std::size_t start = 0; start < knots.size();) {
    std::size_t end = start;
    while (end + 1 < knots.size() && knots[end + 1] == knots[start]) ++end;
    const std::size_t multiplicity = end - start + 1;
    const bool at_end = start == 0 || end == knots.size() - 1;
    const std::size_t allowed = static_cast<std::size_t>(degree) + (at_end ? 1 : 0);
    if (multiplicity > allowed)
      fail(field, std::to_string(start), format_number(knots[start]),
           fmt::format("multiplicity {} exceeds {} ({} knots allow at most degree{})", multiplicity,
                       allowed, at_end ? "end" : "interior", at_end ? "+1" : ""));
    start = end + 1;
  }
  if (!(knots[degree] < knots[count]))
    fail(field, std::to_string(degree), format_number(knots[degree]),
         fmt::format("empty parameter domain: knots[{}] must be < knots[{}] = {}", degree, count,
                     format_number(knots[count])));
}

void SurfaceChecker::check_at_most(const std::string& field, std::size_t size, std::size_t max,
                                   std::string_view what) const {
  if (size > max)
    fail(field, kLengthIndex, std::to_string(size), fmt::format("at most {} {}", max, what));
}

namespace {

void check_control_net(const Surface& s, const SurfaceChecker& check) {
  const std::size_t expected = static_cast<std::size_t>(s.count_u) * s.count_v;
  if (s.points.size() != expected)
    check.fail("points", kLengthIndex, std::to_string(s.points.size()),
               fmt::format("need count_u * count_v = {} points", expected));
  if (s.weights.size() != expected)
    check.fail("weights", kLengthIndex, std::to_string(s.weights.size()),
               fmt::format("need count_u * count_v = {} weights", expected));
  for (std::size_t k = 0; k < expected; ++k) {
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(s.points[k][c]))
        check.fail("points", fmt::format("{}][{}", k, c), format_number(s.points[k][c]),
                   "coordinates must be finite");
    if (!std::isfinite(s.weights[k]) || !(s.weights[k] > 0))
      check.fail("weights", std::to_string(k), format_number(s.weights[k]),
                 "weights must be finite and > 0");
  }
}

}  // namespace

void validate_surface_sizes(const Surface& s, int surface_index, std::string_view origin) {
  const SurfaceChecker check(s, surface_index, origin);
  check.check_degree("degree_u", s.degree_u);
  check.check_degree("degree_v", s.degree_v);
  check.check_count("count_u", "", s.count_u, s.degree_u, kMaxCountPerDirection);
  check.check_count("count_v", "", s.count_v, s.degree_v, kMaxCountPerDirection);
  if (static_cast<std::int64_t>(s.count_u) * s.count_v > kMaxControlPointsPerSurface)
    check.fail(
        "count_v", "", std::to_string(s.count_v),
        fmt::format("count_u * count_v = {} exceeds the limit of {} control points",
                    static_cast<std::int64_t>(s.count_u) * s.count_v, kMaxControlPointsPerSurface));
}

void validate_surface(const Surface& s, int surface_index, std::string_view origin) {
  if (s.is_tspline()) {
    validate_tspline(*s.tspline, origin);
    // The influence index's size bounds are part of what makes a T-spline evaluable.
    (void)TSplineInfluence(*s.tspline, origin);
    return;
  }
  validate_surface_sizes(s, surface_index, origin);
  const SurfaceChecker check(s, surface_index, origin);
  check.check_knots("knots_u", s.knots_u, s.degree_u, s.count_u);
  check.check_knots("knots_v", s.knots_v, s.degree_v, s.count_v);
  check_control_net(s, check);
  if (s.trim) validate_trim(s, surface_index, origin);
}

void validate_scene(const Scene& scene, std::string_view origin) {
  if (scene.surfaces.empty())
    throw InputError(fmt::format("{}: surfaces = []: a scene needs at least one surface", origin));
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
    validate_surface(scene.surfaces[i], static_cast<int>(i), origin);
}

}  // namespace nurbs
