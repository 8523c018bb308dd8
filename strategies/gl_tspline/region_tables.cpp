#include "strategies/gl_tspline/region_tables.h"

#include <algorithm>

namespace nurbs::gl_tspline {
namespace {

template <typename T>
void pad_to_rows(std::vector<T>& values, int channels) {
  const std::size_t texels = values.size() / static_cast<std::size_t>(channels);
  values.resize(static_cast<std::size_t>(linear_rows(texels)) * kLinearWidth *
                    static_cast<std::size_t>(channels),
                T(0));
}

}  // namespace

int linear_rows(std::size_t elements) {
  return static_cast<int>(std::max<std::size_t>(1, (elements + kLinearWidth - 1) / kLinearWidth));
}

RegionTables make_region_tables(const TSplineSurface& s, const TSplineInfluence& index) {
  RegionTables t;
  t.degree_u = s.degree_u;
  t.degree_v = s.degree_v;
  t.points = s.count();
  t.homogeneous = homogeneous_points(s);
  for (double knot : s.knots_u) t.knots_u.push_back(static_cast<float>(knot));
  for (double knot : s.knots_v) t.knots_v.push_back(static_cast<float>(knot));
  for (int cu = 0; cu < index.cells_u(); ++cu)
    for (int cv = 0; cv < index.cells_v(); ++cv) {
      t.offsets.push_back(static_cast<std::int32_t>(t.entries));
      const double u0 = index.breaks_u()[static_cast<std::size_t>(cu)];
      const double v0 = index.breaks_v()[static_cast<std::size_t>(cv)];
      int count = 0;
      for (const int* k = index.active_begin(cu, cv); k != index.active_end(cu, cv); ++k) {
        const int su = local_span(s.degree_u, s.local_knots_u(*k), u0, false);
        const int sv = local_span(s.degree_v, s.local_knots_v(*k), v0, false);
        if (su < 0 || sv < 0) continue;  // as evaluate_tspline: zero on this region
        t.active.insert(t.active.end(), {*k, su, sv, 0});
        ++t.entries;
        ++count;
      }
      t.max_active = std::max(t.max_active, count);
    }
  t.regions = t.offsets.size();
  t.offsets.push_back(static_cast<std::int32_t>(t.entries));
  pad_to_rows(t.knots_u, 1);
  pad_to_rows(t.knots_v, 1);
  pad_to_rows(t.offsets, 1);
  pad_to_rows(t.active, 4);
  return t;
}

std::vector<float> homogeneous_points(const TSplineSurface& s) {
  std::vector<float> h;
  h.reserve(s.count() * 4);
  for (std::size_t k = 0; k < s.count(); ++k) {
    const double w = s.weights[k];
    for (int c = 0; c < 3; ++c) h.push_back(static_cast<float>(s.points[k][c] * w));
    h.push_back(static_cast<float>(w));
  }
  pad_to_rows(h, 4);
  return h;
}

SampleTable make_sample_table(const TSplineInfluence& index, const SurfaceSamples& samples) {
  SampleTable t;
  t.count = samples.count();
  t.width = static_cast<int>(std::clamp<std::size_t>(t.count, 1, kLinearWidth));
  t.height = static_cast<int>((std::max<std::size_t>(t.count, 1) + t.width - 1) / t.width);
  const std::size_t texels = static_cast<std::size_t>(t.width) * t.height;
  t.uv.reserve(texels * 2);
  t.regions.reserve(texels);
  for (std::size_t k = 0; k < texels; ++k) {
    const std::size_t sample = k < t.count ? k : 0;
    const double u = t.count ? samples.u_of(sample) : 0.0;
    const double v = t.count ? samples.v_of(sample) : 0.0;
    t.uv.push_back(static_cast<float>(u));
    t.uv.push_back(static_cast<float>(v));
    t.regions.push_back(index.cell_u(u) * index.cells_v() + index.cell_v(v));
  }
  return t;
}

int accumulation_passes(int max_active, int points_per_pass) {
  return (max_active + points_per_pass - 1) / points_per_pass;
}

}  // namespace nurbs::gl_tspline
