#include "reference/tspline_refinement.h"

#include <algorithm>
#include <iterator>
#include <map>
#include <optional>
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

namespace {

std::vector<double> knot_key(const TSplineSurface& s, std::size_t k) {
  std::vector<double> key(s.local_knots_u(k), s.local_knots_u(k) + s.degree_u + 2);
  key.insert(key.end(), s.local_knots_v(k), s.local_knots_v(k) + s.degree_v + 2);
  return key;
}

// The knot `fine` has and `coarse` lacks (vectors of n knots), or none; more than one is refused.
std::optional<double> gained_knot(const double* coarse, const double* fine, int n) {
  std::vector<double> gained;
  std::set_difference(fine, fine + n, coarse, coarse + n, std::back_inserter(gained));
  if (gained.size() > 1)
    throw std::invalid_argument("refine_onto: a function gains more than one knot in a direction");
  return gained.empty() ? std::nullopt : std::optional<double>(gained[0]);
}

}  // namespace

TSplineSurface refine_onto(const TSplineSurface& coarse, const TSplineSurface& fine) {
  if (fine.count() < coarse.count() || fine.degree_u != coarse.degree_u ||
      fine.degree_v != coarse.degree_v)
    throw std::invalid_argument("refine_onto: fine must extend coarse at the same degrees");
  TSplineSurface refined = coarse;
  for (std::size_t k = 0; k < coarse.count(); ++k) {
    const auto u = gained_knot(coarse.local_knots_u(k), fine.local_knots_u(k), coarse.degree_u + 2);
    const auto v = gained_knot(coarse.local_knots_v(k), fine.local_knots_v(k), coarse.degree_v + 2);
    std::vector<std::size_t> pieces{k};
    if (u) {
      split_blending_function_u(refined, k, *u);
      pieces.push_back(refined.count() - 1);
    }
    if (v)
      for (std::size_t piece : pieces) split_blending_function_v(refined, piece, *v);
  }
  merge_equal_blending_functions(refined);
  if (refined.count() != fine.count())
    throw std::invalid_argument("refine_onto: the split functions are not the fine mesh's");
  std::map<std::vector<double>, std::size_t> by_key;
  for (std::size_t k = 0; k < refined.count(); ++k) by_key.emplace(knot_key(refined, k), k);
  TSplineSurface out = fine;
  for (std::size_t k = 0; k < fine.count(); ++k) {
    const auto it = by_key.find(knot_key(fine, k));
    if (it == by_key.end())
      throw std::invalid_argument("refine_onto: a fine function is no piece of the coarse ones");
    out.points[k] = refined.points[it->second];
    out.weights[k] = refined.weights[it->second];
  }
  return out;
}

}  // namespace nurbs
