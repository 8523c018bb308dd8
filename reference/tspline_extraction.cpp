#include "reference/tspline_extraction.h"

#include <fmt/format.h>

#include <algorithm>

#include "reference/bezier_decomposition.h"

namespace nurbs {

namespace {

using LD = long double;

// Bernstein coefficients c on [lo, hi] -> those of the same polynomial on [lo + x (hi - lo), hi]:
// de Casteljau at x, in place; entry i ends on level p-i, index i (the right piece).
void keep_right(int degree, LD x, LD* c) {
  for (int r = 1; r <= degree; ++r)
    for (int i = 0; i <= degree - r; ++i) c[i] = (1 - x) * c[i] + x * c[i + 1];
}
// ... on [lo, lo + y (hi - lo)]: entry i ends on level i, index 0 (the left piece).
void keep_left(int degree, LD y, LD* c) {
  for (int r = 1; r <= degree; ++r)
    for (int i = degree; i >= r; --i) c[i] = (1 - y) * c[i - 1] + y * c[i];
}

}  // namespace

void local_bernstein_coefficients(int degree, const double* local, double a, double b, LD* out) {
  const int p = degree, count = 2 * p + 1;
  LD padded[3 * kMaxOrder];
  padded_local_knots(p, local, padded);
  std::vector<Vec4<LD>> unit(count, Vec4<LD>{}),
      segments(static_cast<std::size_t>(p + 1) * (p + 1));
  unit[p][0] = 1;
  decompose_curves<LD>(p, count, padded, {unit.data(), 1, 1, 1}, {segments.data(), 1, 1, 1});
  // Segment g is the g-th non-empty span of the function's support [local[0], local[p+1]].
  int segment = 0, span = 0;
  for (span = 0; span <= p; ++span) {
    if (!(local[span] < local[span + 1])) continue;
    if (local[span] <= a && b <= local[span + 1]) break;
    ++segment;
  }
  for (int k = 0; k <= p; ++k)
    out[k] = segments[static_cast<std::size_t>(segment) * (p + 1) + k][0];
  const LD lo = local[span], hi = local[span + 1];
  if (LD(a) > lo) keep_right(p, (LD(a) - lo) / (hi - lo), out);
  if (LD(b) < hi) keep_left(p, (LD(b) - LD(a)) / (hi - LD(a)), out);
}

TSplineExtraction extract_bezier_elements(const TSplineSurface& s, const TSplineInfluence& index) {
  TSplineExtraction out;
  out.degree_u = s.degree_u;
  out.degree_v = s.degree_v;
  const int p = s.degree_u, q = s.degree_v;
  out.elements.reserve(static_cast<std::size_t>(index.cells_u()) * index.cells_v());
  for (int cu = 0; cu < index.cells_u(); ++cu)
    for (int cv = 0; cv < index.cells_v(); ++cv) {
      BezierElement e;
      e.cell_u = cu;
      e.cell_v = cv;
      e.u0 = index.breaks_u()[cu];
      e.u1 = index.breaks_u()[cu + 1];
      e.v0 = index.breaks_v()[cv];
      e.v1 = index.breaks_v()[cv + 1];
      e.functions.assign(index.active_begin(cu, cv), index.active_end(cu, cv));
      e.extraction.resize(e.functions.size() * (p + 1) * (q + 1));
      LD row_u[kMaxOrder], row_v[kMaxOrder];
      for (std::size_t r = 0; r < e.functions.size(); ++r) {
        const int k = e.functions[r];
        local_bernstein_coefficients(p, s.local_knots_u(k), e.u0, e.u1, row_u);
        local_bernstein_coefficients(q, s.local_knots_v(k), e.v0, e.v1, row_v);
        LD* c = e.extraction.data() + r * (p + 1) * (q + 1);
        for (int a = 0; a <= p; ++a)
          for (int b = 0; b <= q; ++b) c[a * (q + 1) + b] = row_u[a] * row_v[b];
      }
      out.elements.push_back(std::move(e));
    }
  return out;
}

void element_homogeneous_points(const TSplineSurface& s, const TSplineExtraction& x,
                                const BezierElement& e, Vec4<LD>* sum) {
  const std::size_t n = static_cast<std::size_t>(x.degree_u + 1) * (x.degree_v + 1);
  std::fill(sum, sum + n, Vec4<LD>{});
  for (std::size_t r = 0; r < e.functions.size(); ++r) {
    const int k = e.functions[r];
    const LD w = s.weights[k];
    const Vec4<LD> point{LD(s.points[k][0]) * w, LD(s.points[k][1]) * w, LD(s.points[k][2]) * w, w};
    const LD* c = e.extraction.data() + r * n;
    for (std::size_t j = 0; j < n; ++j)
      for (int d = 0; d < 4; ++d) sum[j][d] += c[j] * point[d];
  }
}

bool same_extraction_topology(const TSplineSurface& a, const TSplineSurface& b) {
  return a.degree_u == b.degree_u && a.degree_v == b.degree_v && a.count() == b.count() &&
         a.knots_u == b.knots_u && a.knots_v == b.knots_v && a.u_min == b.u_min &&
         a.u_max == b.u_max && a.v_min == b.v_min && a.v_max == b.v_max;
}

Surface bezier_patch(const TSplineSurface& s, const TSplineExtraction& x, const BezierElement& e) {
  const int p = x.degree_u, q = x.degree_v;
  std::vector<Vec4<LD>> sum(static_cast<std::size_t>(p + 1) * (q + 1));
  element_homogeneous_points(s, x, e, sum.data());
  Surface patch;
  patch.name = fmt::format("{} element ({}, {})", s.name, e.cell_u, e.cell_v);
  patch.degree_u = p;
  patch.degree_v = q;
  patch.count_u = p + 1;
  patch.count_v = q + 1;
  patch.knots_u.assign(p + 1, e.u0);
  patch.knots_u.insert(patch.knots_u.end(), p + 1, e.u1);
  patch.knots_v.assign(q + 1, e.v0);
  patch.knots_v.insert(patch.knots_v.end(), q + 1, e.v1);
  for (const Vec4<LD>& h : sum) {
    patch.points.push_back({double(h[0] / h[3]), double(h[1] / h[3]), double(h[2] / h[3])});
    patch.weights.push_back(double(h[3]));
  }
  return patch;
}

}  // namespace nurbs
