// A T-spline surface in its point-based form (001 eq. 4-5; Sederberg, Zheng, Bakenov, Nasri,
// "T-splines and T-NURCCs", 2003): control points with weights, each carrying its own local knot
// vectors of degree+2 knots in u and in v, and
//   S(u, v) = sum_k w_k P_k N[u_k](u) N[v_k](v) / sum_k w_k N[u_k](u) N[v_k](v).
// The reference evaluates it in extended precision, reusing Piegl & Tiller's A2.2 / A2.3 on each
// local knot vector (nurbs_math.h) -- no second basis implementation.
//
// Degrees are odd (1, 3, 5, ...): the classic definition puts each control point on a knot line,
// at the middle knot of its local vectors; even degrees put knot lines through face centres and
// are not supported here.
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/reference_evaluator.h"
#include "reference/sampling.h"
#include "reference/surface.h"

namespace nurbs {

// Bounds checked before anything is allocated from a file's counts.
inline constexpr std::int64_t kMaxTSplineControlPoints = 1 << 20;
// The influence index stores one list per region (cell of the knot-line grid): bounded so an
// adversarial knot layout cannot make it quadratic in memory.
inline constexpr std::int64_t kMaxTSplineRegions = 1 << 22;
inline constexpr std::int64_t kMaxTSplineRegionEntries = 1 << 26;

struct TSplineSurface {
  std::string name;
  int degree_u = 3;
  int degree_v = 3;
  std::vector<Point3> points;   // Cartesian, NOT pre-multiplied by the weight
  std::vector<double> weights;  // > 0
  // Point k's local knot vectors: knots_u[k*(degree_u+2) .. +degree_u+1], likewise v.
  std::vector<double> knots_u;
  std::vector<double> knots_v;
  // The parameter domain. A point-based spline does not imply one (its blending functions sum to
  // one only where the T-mesh says so), so it is stored: the T-mesh inference sets it.
  double u_min = 0, u_max = 0, v_min = 0, v_max = 0;

  std::size_t count() const { return points.size(); }
  const double* local_knots_u(std::size_t k) const { return knots_u.data() + k * (degree_u + 2); }
  const double* local_knots_v(std::size_t k) const { return knots_v.data() + k * (degree_v + 2); }
};

// The one-line shape of every T-spline and T-mesh error, as an InputError (the CLI's exit 2):
// "<origin>: <kind> '<name>': <where> = <value>: <rule>", file-provided parts escaped.
[[noreturn]] void throw_tspline_error(std::string_view origin, std::string_view kind,
                                      std::string_view name, const std::string& where,
                                      const std::string& value, const std::string& rule);

// Throws InputError "<origin>: tspline '<name>': point 17 knots_u[2] = nan: <rule>" for the first
// violated rule: odd degree in 1..kMaxDegree, 1..kMaxTSplineControlPoints points, one weight and
// degree+2 knots per point in each direction, knots finite and non-decreasing with a non-empty
// support (first < last), coordinates finite, weights finite and > 0, a finite non-empty domain.
void validate_tspline(const TSplineSurface& surface, std::string_view origin);

// 001 Fig 7: the control points whose blending function is non-zero, per region. Here a region is
// a cell of the grid of every distinct local knot value inside the domain -- a refinement of
// 001's per-face regions (each of theirs is a union of these cells), chosen because it needs no
// T-mesh faces: it works on the point-based form alone. On a cell every blending function is one
// polynomial, so the same cells are the Bézier extraction's elements. A query is two binary
// searches (O(log n)).
class TSplineInfluence {
 public:
  // Throws InputError when the cell grid or its lists exceed kMaxTSplineRegions /
  // kMaxTSplineRegionEntries.
  TSplineInfluence(const TSplineSurface& surface, std::string_view origin);

  const std::vector<double>& breaks_u() const { return breaks_u_; }
  const std::vector<double>& breaks_v() const { return breaks_v_; }
  int cells_u() const { return static_cast<int>(breaks_u_.size()) - 1; }
  int cells_v() const { return static_cast<int>(breaks_v_.size()) - 1; }
  // The cell holding u: breaks[c] <= u < breaks[c+1], the domain end in the last cell, anything
  // outside the domain in the nearest cell.
  int cell_u(double u) const { return find_cell(breaks_u_, u); }
  int cell_v(double v) const { return find_cell(breaks_v_, v); }
  // Control points whose support contains cell (cu, cv), ascending.
  const int* active_begin(int cu, int cv) const { return points_.data() + offsets_[index(cu, cv)]; }
  const int* active_end(int cu, int cv) const {
    return points_.data() + offsets_[index(cu, cv) + 1];
  }

 private:
  static int find_cell(const std::vector<double>& breaks, double t);
  std::size_t index(int cu, int cv) const { return static_cast<std::size_t>(cu) * cells_v() + cv; }
  std::vector<double> breaks_u_, breaks_v_;
  std::vector<std::size_t> offsets_;  // CSR over cells
  std::vector<int> points_;
};

// The span s (local[s] <= t < local[s+1], non-empty) of a local knot vector of degree+2 knots
// holding t, or -1 outside the support. At the support's right end t == local[degree+1] the
// function is zero (half-open spans) unless `closed_right`, which the domain's end takes (Piegl &
// Tiller's convention: the end parameter belongs to the last non-empty span).
int local_span(int degree, const double* local, double t, bool closed_right);

// The local knot vector (degree+2 knots) with degree copies of each end knot added: 3*degree+2
// knots, clamped at both ends, on which the local function is basis function number `degree` of
// 2*degree+1 (the padding changes the neighbours, never it).
template <typename T>
void padded_local_knots(int degree, const double* local, T* padded) {
  for (int i = 0; i < 3 * degree + 2; ++i)
    padded[i] = T(local[std::clamp(i - degree, 0, degree + 1)]);
}

// Value (and derivatives up to `order` <= 2) at t of the one B-spline basis function on the local
// knot vector `local` (degree+2 knots), whose span holding t is `span`: A2.2 / A2.3 on the padded
// local vector.
template <typename T>
void local_basis(int degree, const double* local, int span, T t, int order, T out[3]) {
  T padded[3 * kMaxOrder];
  padded_local_knots(degree, local, padded);
  const int padded_span = degree + span;
  if (order == 0) {
    T basis[kMaxOrder];
    basis_functions(padded_span, t, degree, padded, basis);
    out[0] = basis[degree - span];
    out[1] = out[2] = T(0);
    return;
  }
  T ders[3][kMaxOrder]{};  // zeroed only to quiet -Wmaybe-uninitialized
  basis_function_derivatives(padded_span, t, degree, order, padded, ders);
  for (int k = 0; k < 3; ++k) out[k] = k <= order ? ders[k][degree - span] : T(0);
}

// Point, first derivatives and unit normal (zero where Su x Sv is rounding noise: no limit
// normals at collapsed edges, unlike surface_normal for NURBS).
template <typename T>
struct TSplineEvaluation {
  Vec3<T> point{}, su{}, sv{}, normal{};
};

namespace detail {

// The rational combination over the given control points, each evaluated on the span the
// `span_of` callback picks (returns -1 for a function that is zero there).
template <typename T, typename PointRange, typename SpanOf>
TSplineEvaluation<T> combine_tspline(const TSplineSurface& s, const PointRange& points, T u, T v,
                                     int order, SpanOf&& span_of) {
  Vec4<T> sum{}, sum_u{}, sum_v{};
  for (const int k : points) {
    const double* ku = s.local_knots_u(k);
    const double* kv = s.local_knots_v(k);
    int su = -1, sv = -1;
    span_of(k, ku, kv, su, sv);
    if (su < 0 || sv < 0) continue;
    T nu[3], nv[3];
    local_basis(s.degree_u, ku, su, u, order, nu);
    local_basis(s.degree_v, kv, sv, v, order, nv);
    const T w = T(s.weights[k]);
    const Vec4<T> p{T(s.points[k][0]) * w, T(s.points[k][1]) * w, T(s.points[k][2]) * w, w};
    for (int c = 0; c < 4; ++c) {
      sum[c] += nu[0] * nv[0] * p[c];
      sum_u[c] += nu[1] * nv[0] * p[c];
      sum_v[c] += nu[0] * nv[1] * p[c];
    }
  }
  TSplineEvaluation<T> out;
  for (int c = 0; c < 3; ++c) out.point[c] = sum[c] / sum[3];
  if (order == 0) return out;
  for (int c = 0; c < 3; ++c) {
    out.su[c] = (sum_u[c] - sum_u[3] * out.point[c]) / sum[3];
    out.sv[c] = (sum_v[c] - sum_v[3] * out.point[c]) / sum[3];
  }
  normalize_if_resolved(cross(out.su, out.sv), out.su, out.sv, out.normal);
  return out;
}

struct ActiveRange {
  const int *first, *last;
  const int* begin() const { return first; }
  const int* end() const { return last; }
};

}  // namespace detail

// The reference: the control points of (u, v)'s region from the influence index, each blending
// function on the span that holds the region (so a region's polynomial is used up to its closed
// edges). order 0: point only; 1: also Su, Sv and the normal.
template <typename T = long double>
TSplineEvaluation<T> evaluate_tspline(const TSplineSurface& s, const TSplineInfluence& index,
                                      double u, double v, int order = 1) {
  const int cu = index.cell_u(u), cv = index.cell_v(v);
  const double cell_u0 = index.breaks_u()[cu], cell_v0 = index.breaks_v()[cv];
  const detail::ActiveRange active{index.active_begin(cu, cv), index.active_end(cu, cv)};
  return detail::combine_tspline<T>(s, active, T(u), T(v), order,
                                    [&](int, const double* ku, const double* kv, int& su, int& sv) {
                                      su = local_span(s.degree_u, ku, cell_u0, false);
                                      sv = local_span(s.degree_v, kv, cell_v0, false);
                                    });
}

// The O(n) oracle: every control point, each function zero outside its half-open support (closed
// at the domain's end). Shares only local_basis with evaluate_tspline, not the region lists.
template <typename T = long double>
TSplineEvaluation<T> evaluate_tspline_brute_force(const TSplineSurface& s, double u, double v,
                                                  int order = 1) {
  std::vector<int> all(s.count());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  const bool u_end = !(u < s.u_max), v_end = !(v < s.v_max);
  return detail::combine_tspline<T>(s, all, T(u), T(v), order,
                                    [&](int, const double* ku, const double* kv, int& su, int& sv) {
                                      su = local_span(s.degree_u, ku, u, u_end);
                                      sv = local_span(s.degree_v, kv, v, v_end);
                                    });
}

// Sum of the (unweighted) blending functions N[u_k](u) N[v_k](v) over every control point, by the
// brute-force rule: 1 everywhere in the domain of a standard (e.g. analysis-suitable) T-spline.
template <typename T = long double>
T tspline_blending_sum(const TSplineSurface& s, double u, double v) {
  const bool u_end = !(u < s.u_max), v_end = !(v < s.v_max);
  T sum = T(0);
  for (std::size_t k = 0; k < s.count(); ++k) {
    const int su = local_span(s.degree_u, s.local_knots_u(k), u, u_end);
    const int sv = local_span(s.degree_v, s.local_knots_v(k), v, v_end);
    if (su < 0 || sv < 0) continue;
    T nu[3], nv[3];
    local_basis(s.degree_u, s.local_knots_u(k), su, T(u), 0, nu);
    local_basis(s.degree_v, s.local_knots_v(k), sv, T(v), 0, nv);
    sum += nu[0] * nv[0];
  }
  return sum;
}

// Every sample of `samples` (docs/design.md §Sampling) through evaluate_tspline in extended
// precision (long double, or __float128 on request), in the ReferenceSurface shape the harness
// compares NURBS strategies with.
ReferenceSurface evaluate_tspline_reference(
    const TSplineSurface& surface, const TSplineInfluence& index, const SurfaceSamples& samples,
    bool with_normals, ReferencePrecision precision = ReferencePrecision::long_double);

// Distinct knot values strictly inside [lo, hi], with lo and hi: the influence index's cell
// boundaries (its breaks_u/v), and the knot lines a span grid samples on a T-spline.
std::vector<double> tspline_cell_breaks(const std::vector<double>& knots, double lo, double hi);

// The scene's surface of a T-spline (reference/surface.h, Surface::tspline): its name and degrees,
// the T-spline shared.
Surface make_tspline_surface(TSplineSurface tspline);

}  // namespace nurbs
