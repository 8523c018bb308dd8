// T-meshes for the T-spline tests: the tensor mesh of a NURBS surface (whose T-spline must be that
// NURBS), and random meshes with T-junctions that are analysis-suitable by construction.
#pragma once

#include <algorithm>
#include <vector>

#include "reference/surface.h"
#include "reference/tmesh.h"
#include "tests/reference/random_nurbs.h"

namespace nurbs::test {

// The T-mesh of a NURBS surface's full control grid (reference/tmesh.h).
using nurbs::tensor_tmesh;

// Every row a full line; each interior column present on a random subset of the row intervals
// (the (degree_s+1)/2 outer columns on each side always full). Every T-junction then has a
// vertical extension only, and no horizontal one to meet: analysis-suitable (Li et al. 2012).
// Knot values are small dyadics with zero intervals allowed at the ends (clamped-like boundary).
inline TMesh random_vertical_tmesh(Rng& rng, int degree_s, int degree_t, int columns, int rows,
                                   bool rational) {
  TMesh m;
  m.name = "random-t";
  m.degree_s = degree_s;
  m.degree_t = degree_t;
  auto knot_lines = [&](int count, int degree) {
    std::vector<double> k;
    double x = uniform_int(rng, -4, 4) / 8.0;
    const int ends = (degree - 1) / 2;
    for (int i = 0; i < count; ++i) {
      k.push_back(x);
      const bool end = i < ends || i >= count - 1 - ends;
      x += end ? 0.0 : uniform_int(rng, 1, 4) / 8.0;
    }
    return k;
  };
  m.knots_s = knot_lines(columns, degree_s);
  m.knots_t = knot_lines(rows, degree_t);
  const int full = (degree_s + 1) / 2;
  // present[i][j]: column i has the segment [j, j+1].
  std::vector<std::vector<bool>> present(columns, std::vector<bool>(rows - 1, true));
  for (int i = full; i < columns - full; ++i)
    for (int j = 0; j + 1 < rows; ++j) present[i][j] = uniform_int(rng, 0, 9) < 6;
  std::vector<std::vector<int>> id(columns, std::vector<int>(rows, -1));
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < rows; ++j) {
      const bool below = j > 0 && present[i][j - 1], above = j + 1 < rows && present[i][j];
      if (!below && !above) continue;
      id[i][j] = static_cast<int>(m.vertices.size());
      m.vertices.push_back({i, j});
      m.points.push_back({uniform_int(rng, -512, 512) / 64.0, uniform_int(rng, -512, 512) / 64.0,
                          uniform_int(rng, -512, 512) / 64.0});
      m.weights.push_back(rational ? uniform_int(rng, 2, 32) / 8.0 : 1.0);
    }
  for (int j = 0; j < rows; ++j) {
    int previous = -1;
    for (int i = 0; i < columns; ++i) {
      if (id[i][j] < 0) continue;
      if (previous >= 0) m.edges.push_back({previous, id[i][j]});
      previous = id[i][j];
    }
  }
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j + 1 < rows; ++j)
      if (present[i][j]) m.edges.push_back({id[i][j], id[i][j + 1]});
  return m;
}

// `trials` random_vertical_tmesh meshes per degree pair, with 3 + trial % 4 columns and
// 3 + trial % 3 rows beyond the degree.
inline std::vector<TMesh> random_vertical_tmeshes(Rng& rng,
                                                  const std::vector<std::pair<int, int>>& degrees,
                                                  int trials, bool rational) {
  std::vector<TMesh> meshes;
  for (const auto& [p, q] : degrees)
    for (int trial = 0; trial < trials; ++trial)
      meshes.push_back(
          random_vertical_tmesh(rng, p, q, p + 3 + trial % 4, q + 3 + trial % 3, rational));
  return meshes;
}

// (u, v) pairs to test over a T-spline's domain: the corners, every cell break pair of a coarse
// set, and uniformly random ones.
inline std::vector<std::array<double, 2>> domain_samples(Rng& rng, const TSplineSurface& s,
                                                         const std::vector<double>& breaks_u,
                                                         const std::vector<double>& breaks_v,
                                                         int random_count) {
  std::vector<std::array<double, 2>> uv;
  for (double u : breaks_u)
    for (double v : breaks_v) uv.push_back({u, v});
  for (int r = 0; r < random_count; ++r)
    uv.push_back({uniform_real(rng, s.u_min, s.u_max), uniform_real(rng, s.v_min, s.v_max)});
  return uv;
}

}  // namespace nurbs::test
