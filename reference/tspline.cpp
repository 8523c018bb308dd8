#include "reference/tspline.h"

#include <fmt/format.h>

#include <cmath>

#include "reference/error_text.h"
#include "reference/validation.h"

namespace nurbs {

void throw_tspline_error(std::string_view origin, std::string_view kind, std::string_view name,
                         const std::string& where, const std::string& value,
                         const std::string& rule) {
  throw InputError(fmt::format("{}: {} '{}': {} = {}: {}", printable(origin), kind,
                               printable(name, kQuotedValueBytes), where,
                               printable(value, kQuotedValueBytes), rule));
}

namespace {

[[noreturn]] void fail(std::string_view origin, const TSplineSurface& s, const std::string& where,
                       const std::string& value, const std::string& rule) {
  throw_tspline_error(origin, "tspline", s.name, where, value, rule);
}

void check_local_knots(std::string_view origin, const TSplineSurface& s, std::size_t k,
                       const char* field, int degree, const double* local) {
  for (int i = 0; i < degree + 2; ++i) {
    const std::string where = fmt::format("point {} {}[{}]", k, field, i);
    if (!std::isfinite(local[i]))
      fail(origin, s, where, format_number(local[i]), "knots must be finite");
    if (i > 0 && local[i] < local[i - 1])
      fail(origin, s, where, format_number(local[i]),
           fmt::format("knots must be non-decreasing (previous is {})",
                       format_number(local[i - 1])));
  }
  if (!(local[0] < local[degree + 1]))
    fail(origin, s, fmt::format("point {} {}[{}]", k, field, degree + 1),
         format_number(local[degree + 1]),
         fmt::format("empty support: the last knot must exceed the first ({})",
                     format_number(local[0])));
}

}  // namespace

void validate_tspline(const TSplineSurface& s, std::string_view origin) {
  for (const auto& [field, degree] : {std::pair{"degree_u", s.degree_u}, {"degree_v", s.degree_v}})
    if (degree < 1 || degree > kMaxDegree || degree % 2 == 0)
      fail(origin, s, field, std::to_string(degree),
           fmt::format("degree must be odd and in 1..{} (even degrees put knot lines through face "
                       "centres: not supported)",
                       kMaxDegree));
  const std::size_t n = s.points.size();
  if (n < 1 || static_cast<std::int64_t>(n) > kMaxTSplineControlPoints)
    fail(origin, s, "points length", std::to_string(n),
         fmt::format("need 1 to {} control points", kMaxTSplineControlPoints));
  if (s.weights.size() != n)
    fail(origin, s, "weights length", std::to_string(s.weights.size()),
         fmt::format("need one weight per point ({})", n));
  const std::size_t ku = static_cast<std::size_t>(s.degree_u) + 2;
  const std::size_t kv = static_cast<std::size_t>(s.degree_v) + 2;
  if (s.knots_u.size() != n * ku)
    fail(origin, s, "knots_u length", std::to_string(s.knots_u.size()),
         fmt::format("need degree_u + 2 = {} knots per point ({})", ku, n * ku));
  if (s.knots_v.size() != n * kv)
    fail(origin, s, "knots_v length", std::to_string(s.knots_v.size()),
         fmt::format("need degree_v + 2 = {} knots per point ({})", kv, n * kv));
  for (std::size_t k = 0; k < n; ++k) {
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(s.points[k][c]))
        fail(origin, s, fmt::format("point {} xyz[{}]", k, c), format_number(s.points[k][c]),
             "coordinates must be finite");
    if (!std::isfinite(s.weights[k]) || !(s.weights[k] > 0))
      fail(origin, s, fmt::format("point {} weight", k), format_number(s.weights[k]),
           "weights must be finite and > 0");
    check_local_knots(origin, s, k, "knots_u", s.degree_u, s.local_knots_u(k));
    check_local_knots(origin, s, k, "knots_v", s.degree_v, s.local_knots_v(k));
  }
  const double bounds[4] = {s.u_min, s.u_max, s.v_min, s.v_max};
  const char* names[4] = {"u_min", "u_max", "v_min", "v_max"};
  for (int i = 0; i < 4; ++i)
    if (!std::isfinite(bounds[i]))
      fail(origin, s, names[i], format_number(bounds[i]), "the domain must be finite");
  if (!(s.u_min < s.u_max))
    fail(origin, s, "u_max", format_number(s.u_max),
         fmt::format("empty domain: must exceed u_min = {}", format_number(s.u_min)));
  if (!(s.v_min < s.v_max))
    fail(origin, s, "v_max", format_number(s.v_max),
         fmt::format("empty domain: must exceed v_min = {}", format_number(s.v_min)));
}

int local_span(int degree, const double* local, double t, bool closed_right) {
  if (t < local[0] || t > local[degree + 1]) return -1;
  if (t == local[degree + 1]) {
    if (!closed_right) return -1;
    int s = degree;
    while (!(local[s] < local[s + 1])) --s;
    return s;
  }
  // Last knot <= t: the end of a run of equal knots, so the span is non-empty.
  return static_cast<int>(std::upper_bound(local, local + degree + 2, t) - local) - 1;
}

std::vector<double> tspline_cell_breaks(const std::vector<double>& knots, double lo, double hi) {
  std::vector<double> breaks{lo, hi};
  for (double k : knots)
    if (k > lo && k < hi) breaks.push_back(k);
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  return breaks;
}

namespace {

// Cells [first, last) a support [a, b] covers (a support's ends inside the domain are breaks).
std::pair<int, int> covered_cells(const std::vector<double>& breaks, double a, double b) {
  const int first =
      static_cast<int>(std::lower_bound(breaks.begin(), breaks.end(), a) - breaks.begin());
  const int last =
      static_cast<int>(std::upper_bound(breaks.begin(), breaks.end(), b) - breaks.begin()) - 1;
  const int cells = static_cast<int>(breaks.size()) - 1;
  return {std::min(first, cells), std::clamp(last, 0, cells)};
}

}  // namespace

TSplineInfluence::TSplineInfluence(const TSplineSurface& s, std::string_view origin)
    : breaks_u_(tspline_cell_breaks(s.knots_u, s.u_min, s.u_max)),
      breaks_v_(tspline_cell_breaks(s.knots_v, s.v_min, s.v_max)) {
  const std::int64_t cells = static_cast<std::int64_t>(cells_u()) * cells_v();
  if (cells > kMaxTSplineRegions)
    throw InputError(fmt::format("{}: tspline '{}': {} x {} regions exceed the limit of {}",
                                 printable(origin), printable(s.name, kQuotedValueBytes), cells_u(),
                                 cells_v(), kMaxTSplineRegions));
  // Two passes (count, then fill) so the lists are one CSR array.
  std::vector<std::array<int, 4>> ranges(s.count());
  offsets_.assign(static_cast<std::size_t>(cells) + 1, 0);
  std::int64_t entries = 0;
  for (std::size_t k = 0; k < s.count(); ++k) {
    const double* ku = s.local_knots_u(k);
    const double* kv = s.local_knots_v(k);
    const auto [u0, u1] = covered_cells(breaks_u_, ku[0], ku[s.degree_u + 1]);
    const auto [v0, v1] = covered_cells(breaks_v_, kv[0], kv[s.degree_v + 1]);
    ranges[k] = {u0, u1, v0, v1};
    for (int cu = u0; cu < u1; ++cu)
      for (int cv = v0; cv < v1; ++cv) ++offsets_[index(cu, cv) + 1];
    entries += static_cast<std::int64_t>(std::max(u1 - u0, 0)) * std::max(v1 - v0, 0);
    if (entries > kMaxTSplineRegionEntries)
      throw InputError(fmt::format(
          "{}: tspline '{}': region lists exceed the limit of {} entries (at point {})",
          printable(origin), printable(s.name, kQuotedValueBytes), kMaxTSplineRegionEntries, k));
  }
  for (std::size_t c = 1; c < offsets_.size(); ++c) offsets_[c] += offsets_[c - 1];
  points_.resize(offsets_.back());
  std::vector<std::size_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t k = 0; k < s.count(); ++k) {
    const auto& r = ranges[k];
    for (int cu = r[0]; cu < r[1]; ++cu)
      for (int cv = r[2]; cv < r[3]; ++cv) points_[fill[index(cu, cv)]++] = static_cast<int>(k);
  }
}

int TSplineInfluence::find_cell(const std::vector<double>& breaks, double t) {
  const int cells = static_cast<int>(breaks.size()) - 1;
  const int c =
      static_cast<int>(std::upper_bound(breaks.begin(), breaks.end(), t) - breaks.begin()) - 1;
  return std::clamp(c, 0, cells - 1);
}

namespace {

template <typename T>
ReferenceSurface tspline_reference(const TSplineSurface& surface, const TSplineInfluence& index,
                                   const SurfaceSamples& samples, bool with_normals) {
  ReferenceSurface out;
  const std::size_t n = samples.count();
  out.positions.resize(n);
  if (with_normals) out.normals.resize(n);
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < n; ++k) {
    const TSplineEvaluation<T> e =
        evaluate_tspline<T>(surface, index, samples.u_of(k), samples.v_of(k), with_normals ? 1 : 0);
    for (int c = 0; c < 3; ++c) {
      out.positions[k][c] = static_cast<double>(e.point[c]);
      if (with_normals) out.normals[k][c] = static_cast<double>(e.normal[c]);
    }
  }
  return out;
}

}  // namespace

ReferenceSurface evaluate_tspline_reference(const TSplineSurface& surface,
                                            const TSplineInfluence& index,
                                            const SurfaceSamples& samples, bool with_normals,
                                            ReferencePrecision precision) {
  return with_reference_scalar(precision, [&]<typename T>() {
    return tspline_reference<T>(surface, index, samples, with_normals);
  });
}

Surface make_tspline_surface(TSplineSurface tspline) {
  Surface s;
  s.name = tspline.name;
  s.degree_u = tspline.degree_u;
  s.degree_v = tspline.degree_v;
  s.tspline = std::make_shared<const TSplineSurface>(std::move(tspline));
  return s;
}

}  // namespace nurbs
