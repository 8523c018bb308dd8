#include "reference/tspline_refinement.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <vector>

namespace nurbs {

namespace {

// The split in one direction: `knots` holds every point's local vectors of `degree`+2 knots,
// `other` those of the other direction (copied to the new point unchanged).
void split(TSplineSurface& s, std::vector<double>& knots, int degree, std::vector<double>& other,
           int other_degree, std::size_t point, double knot) {
  const int n = degree + 2, m = other_degree + 2;
  const std::vector<double> t(knots.begin() + point * n, knots.begin() + (point + 1) * n);
  if (!(t[0] < knot && knot < t[n - 1]))
    throw std::invalid_argument("split_blending_function: knot outside the open support");
  const int p = degree;
  const double c1 = knot < t[p] ? (knot - t[0]) / (t[p] - t[0]) : 1.0;
  const double c2 = knot > t[1] ? (t[p + 1] - knot) / (t[p + 1] - t[1]) : 1.0;
  std::vector<double> merged = t;
  merged.insert(std::upper_bound(merged.begin(), merged.end(), knot), knot);
  const double w = s.weights[point];
  std::copy(merged.begin(), merged.begin() + n, knots.begin() + point * n);
  s.weights[point] = c1 * w;
  knots.insert(knots.end(), merged.begin() + 1, merged.end());
  const std::vector<double> other_knots(other.begin() + point * m, other.begin() + (point + 1) * m);
  other.insert(other.end(), other_knots.begin(), other_knots.end());
  const Point3 xyz = s.points[point];
  s.points.push_back(xyz);
  s.weights.push_back(c2 * w);
}

}  // namespace

void split_blending_function_u(TSplineSurface& s, std::size_t point, double knot) {
  split(s, s.knots_u, s.degree_u, s.knots_v, s.degree_v, point, knot);
}

void split_blending_function_v(TSplineSurface& s, std::size_t point, double knot) {
  split(s, s.knots_v, s.degree_v, s.knots_u, s.degree_u, point, knot);
}

void merge_equal_blending_functions(TSplineSurface& s) {
  const int nu = s.degree_u + 2, nv = s.degree_v + 2;
  std::map<std::vector<double>, std::size_t> first;  // both knot vectors -> merged point
  std::vector<std::array<long double, 4>> sum;       // homogeneous (w P, w) per merged point
  TSplineSurface out = s;
  out.points.clear();
  out.weights.clear();
  out.knots_u.clear();
  out.knots_v.clear();
  for (std::size_t k = 0; k < s.count(); ++k) {
    std::vector<double> key(s.local_knots_u(k), s.local_knots_u(k) + nu);
    key.insert(key.end(), s.local_knots_v(k), s.local_knots_v(k) + nv);
    const auto [it, fresh] = first.emplace(key, sum.size());
    if (fresh) {
      sum.push_back({});
      out.knots_u.insert(out.knots_u.end(), key.begin(), key.begin() + nu);
      out.knots_v.insert(out.knots_v.end(), key.begin() + nu, key.end());
    }
    const long double w = s.weights[k];
    for (int c = 0; c < 3; ++c) sum[it->second][c] += w * s.points[k][c];
    sum[it->second][3] += w;
  }
  for (const auto& h : sum) {
    out.points.push_back({double(h[0] / h[3]), double(h[1] / h[3]), double(h[2] / h[3])});
    out.weights.push_back(double(h[3]));
  }
  s = std::move(out);
}

}  // namespace nurbs
