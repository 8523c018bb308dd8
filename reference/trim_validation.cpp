#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/surface_checker.h"
#include "reference/validation.h"

namespace nurbs {

std::string trim_loop_path(std::size_t loop) {
  return fmt::format("trim.loops[{}]", loop);
}

std::string trim_curve_path(std::size_t loop, std::size_t curve) {
  return fmt::format("trim.loops[{}].curves[{}]", loop, curve);
}

namespace {

std::string point_text(const Point2& p) {
  return fmt::format("[{}, {}]", format_number(p[0]), format_number(p[1]));
}

// A4.1 CurvePoint (reference/nurbs_math.h) on the curve lifted to (w u, w v, 0, w); t in the
// curve's domain.
Point2 curve_point(const TrimCurve& c, double t) {
  std::vector<Vec4<double>> homogeneous(c.points.size());
  for (std::size_t i = 0; i < c.points.size(); ++i)
    homogeneous[i] = {c.points[i][0] * c.weights[i], c.points[i][1] * c.weights[i], 0.0,
                      c.weights[i]};
  const Vec4<double> sum = curve_point_homogeneous(c.degree, static_cast<int>(c.points.size()),
                                                   c.knots.data(), homogeneous.data(), t);
  return {sum[0] / sum[3], sum[1] / sum[3]};
}

// A clamped end (degree+1 equal knots) is exactly its end control point; evaluating would add
// rounding to a value the file states exactly.
Point2 curve_start(const TrimCurve& c) {
  const double start = c.knots[static_cast<std::size_t>(c.degree)];
  return c.knots.front() == start ? c.points.front() : curve_point(c, start);
}

Point2 curve_end(const TrimCurve& c) {
  const double end = c.knots[c.points.size()];
  return c.knots.back() == end ? c.points.back() : curve_point(c, end);
}

void check_curve(const Surface& s, const TrimCurve& c, const std::string& path,
                 const SurfaceChecker& check) {
  const double tolerance = s.trim->tolerance;
  check.check_degree(path + ".degree", c.degree);
  check.check_count(path + ".points", kLengthIndex, static_cast<std::int64_t>(c.points.size()),
                    c.degree, static_cast<std::int64_t>(kMaxTrimPointsPerCurve));
  check.check_knots(path + ".knots", c.knots, c.degree, static_cast<int>(c.points.size()));
  if (c.weights.size() != c.points.size())
    check.fail(path + ".weights", kLengthIndex, std::to_string(c.weights.size()),
               fmt::format("need one weight per control point = {}", c.points.size()));
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    for (int i = 0; i < 2; ++i)
      if (!std::isfinite(c.points[k][i]))
        check.fail(path + ".points", fmt::format("{}][{}", k, i), format_number(c.points[k][i]),
                   "coordinates must be finite");
    if (!std::isfinite(c.weights[k]) || !(c.weights[k] > 0))
      check.fail(path + ".weights", std::to_string(k), format_number(c.weights[k]),
                 "weights must be finite and > 0");
  }
  // With positive weights a rational B-spline curve lies in the convex hull of its control points
  // (The NURBS Book, P4.9), so control points inside the domain put the whole curve inside it.
  // This refuses the rare curve whose control polygon leaves the domain while the curve does not;
  // in exchange no curve point needs to be searched for.
  for (std::size_t k = 0; k < c.points.size(); ++k) {
    const Point2& p = c.points[k];
    if (p[0] < s.u_min() - tolerance || p[0] > s.u_max() + tolerance ||
        p[1] < s.v_min() - tolerance || p[1] > s.v_max() + tolerance)
      check.fail(
          path + ".points", std::to_string(k), point_text(p),
          fmt::format("control point outside the surface's domain [{}, {}] x [{}, {}] by "
                      "more than the tolerance {}",
                      format_number(s.u_min()), format_number(s.u_max()), format_number(s.v_min()),
                      format_number(s.v_max()), format_number(tolerance)));
  }
}

// Each curve's end meets the next one's start, and the last curve's end the first one's start.
void check_closed(const TrimLoop& loop, std::size_t l, double tolerance,
                  const SurfaceChecker& check) {
  const std::size_t n = loop.curves.size();
  for (std::size_t c = 0; c < n; ++c) {
    const std::size_t next = (c + 1) % n;
    const Point2 end = curve_end(loop.curves[c]);
    const Point2 start = curve_start(loop.curves[next]);
    const double gap = std::hypot(end[0] - start[0], end[1] - start[1]);
    if (!(gap <= tolerance))
      check.fail(
          trim_curve_path(l, c) + ".end", "", point_text(end),
          fmt::format("loop not closed: the start of curve {} is {}, a gap of {} > the "
                      "tolerance {}",
                      next, point_text(start), format_number(gap), format_number(tolerance)));
  }
}

}  // namespace

void validate_trim(const Surface& s, int surface_index, std::string_view origin) {
  const Trim& trim = *s.trim;
  const SurfaceChecker check(s, surface_index, origin);
  if (trim.rule != kTrimRuleEvenOdd)
    check.fail("trim.rule", "", fmt::format("{:?}", trim.rule),
               fmt::format("must be \"{}\"", kTrimRuleEvenOdd));
  if (!std::isfinite(trim.tolerance) || !(trim.tolerance > 0))
    check.fail("trim.tolerance", "", format_number(trim.tolerance), "must be finite and > 0");
  if (trim.loops.empty())
    check.fail("trim.loops", kLengthIndex, "0", "a trim needs at least one loop");
  check.check_at_most("trim.loops", trim.loops.size(), kMaxTrimLoops, "loops");
  for (std::size_t l = 0; l < trim.loops.size(); ++l) {
    const TrimLoop& loop = trim.loops[l];
    const std::string curves = trim_loop_path(l) + ".curves";
    if (loop.curves.empty())
      check.fail(curves, kLengthIndex, "0", "a loop needs at least one curve");
    check.check_at_most(curves, loop.curves.size(), kMaxTrimCurvesPerLoop, "curves per loop");
    for (std::size_t c = 0; c < loop.curves.size(); ++c)
      check_curve(s, loop.curves[c], trim_curve_path(l, c), check);
    check_closed(loop, l, trim.tolerance, check);
  }
}

}  // namespace nurbs
