#include "reference/tmesh.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "reference/validation.h"

namespace nurbs {

namespace {

[[noreturn]] void fail(std::string_view origin, const TMesh& m, const std::string& where,
                       const std::string& value, const std::string& rule) {
  throw_tspline_error(origin, "tmesh", m.name, where, value, rule);
}

// Edges of one orientation grouped by the line they lie on: line -> [(from, to)] sorted.
using Segments = std::map<int, std::vector<std::array<int, 2>>>;

struct EdgeLines {
  Segments vertical;    // column i -> row ranges
  Segments horizontal;  // row j -> column ranges
};

EdgeLines edge_lines(const TMesh& m) {
  EdgeLines lines;
  for (const auto& e : m.edges) {
    const TMeshVertex& a = m.vertices[e[0]];
    const TMeshVertex& b = m.vertices[e[1]];
    if (a.i == b.i)
      lines.vertical[a.i].push_back({std::min(a.j, b.j), std::max(a.j, b.j)});
    else
      lines.horizontal[a.j].push_back({std::min(a.i, b.i), std::max(a.i, b.i)});
  }
  for (Segments* s : {&lines.vertical, &lines.horizontal})
    for (auto& [line, segments] : *s) std::sort(segments.begin(), segments.end());
  return lines;
}

// Does a segment of `line` cover position x (ends included)?
bool covers(const Segments& segments, int line, int x) {
  const auto it = segments.find(line);
  if (it == segments.end()) return false;
  for (const auto& seg : it->second)
    if (seg[0] <= x && x <= seg[1]) return true;
  return false;
}

// Is [from, to] of `line` covered by the union of its segments (sorted by start)?
bool covers_range(const Segments& segments, int line, int from, int to) {
  const auto it = segments.find(line);
  if (it == segments.end()) return false;
  int reached = from;
  for (const auto& seg : it->second) {
    if (seg[0] > reached) break;
    reached = std::max(reached, seg[1]);
  }
  return reached >= to;
}

void check_knot_lines(std::string_view origin, const TMesh& m, const char* field,
                      const std::vector<double>& knots) {
  if (knots.size() < 2)
    fail(origin, m, fmt::format("{} length", field), std::to_string(knots.size()),
         "need at least two index lines");
  for (std::size_t k = 0; k < knots.size(); ++k) {
    if (!std::isfinite(knots[k]))
      fail(origin, m, fmt::format("{}[{}]", field, k), format_number(knots[k]),
           "knots must be finite");
    if (k > 0 && knots[k] < knots[k - 1])
      fail(origin, m, fmt::format("{}[{}]", field, k), format_number(knots[k]),
           fmt::format("knots must be non-decreasing (previous is {})",
                       format_number(knots[k - 1])));
  }
}

// The knots a ray from `start` meets stepping by `step` along a line, on perpendicular segments
// covering `at`; `count` of them, the boundary knot (`last` index) filling any missing.
void cast_ray(const Segments& perpendicular, const std::vector<double>& knots, int start, int step,
              int at, int count, double* out) {
  const int last = step > 0 ? static_cast<int>(knots.size()) - 1 : 0;
  int found = 0;
  for (int x = start + step; found < count && x != last + step; x += step)
    if (covers(perpendicular, x, at)) out[found++ * step] = knots[x];
  for (; found < count; ++found) out[found * step] = knots[last];
}

// Index of the `count`-th line met stepping from `start` by `step` on perpendicular segments
// covering `at`; the last line (0 or lines-1) if the mesh ends first; `start` for count 0.
int nth_crossing(const Segments& perpendicular, int lines, int start, int step, int at, int count) {
  const int last = step > 0 ? lines - 1 : 0;
  int x = start;
  for (int found = 0; found < count && x != last;) {
    x += step;
    if (covers(perpendicular, x, at)) ++found;
  }
  return x;
}

}  // namespace

std::string analysis_suitability_violation(const TMesh& m) {
  const EdgeLines lines = edge_lines(m);
  const int columns = static_cast<int>(m.knots_s.size());
  const int rows = static_cast<int>(m.knots_t.size());
  struct Extension {
    int vertex, line, from, to;  // on row/column `line`, index range [from, to]
  };
  std::vector<Extension> horizontal, vertical;
  for (std::size_t k = 0; k < m.vertices.size(); ++k) {
    const auto [i, j] = m.vertices[k];
    if (i == 0 || j == 0 || i == columns - 1 || j == rows - 1) continue;
    // Which directions have an edge: a segment of the row/column through the vertex beyond it.
    auto has = [](const Segments& segments, int line, int x, int step) {
      const auto it = segments.find(line);
      if (it == segments.end()) return false;
      for (const auto& seg : it->second)
        if (step > 0 ? seg[0] == x : seg[1] == x) return true;
      return false;
    };
    const bool east = has(lines.horizontal, j, i, +1), west = has(lines.horizontal, j, i, -1);
    const bool north = has(lines.vertical, i, j, +1), south = has(lines.vertical, i, j, -1);
    if (east + west + north + south != 3) continue;
    const int k_face_s = (m.degree_s + 1) / 2, k_edge_s = (m.degree_s - 1) / 2;
    const int k_face_t = (m.degree_t + 1) / 2, k_edge_t = (m.degree_t - 1) / 2;
    if (!east || !west) {
      const int step = east ? -1 : +1;  // toward the missing edge
      const int a = nth_crossing(lines.vertical, columns, i, step, j, k_face_s);
      const int b = nth_crossing(lines.vertical, columns, i, -step, j, k_edge_s);
      horizontal.push_back({static_cast<int>(k), j, std::min(a, b), std::max(a, b)});
    } else {
      const int step = north ? -1 : +1;
      const int a = nth_crossing(lines.horizontal, rows, j, step, i, k_face_t);
      const int b = nth_crossing(lines.horizontal, rows, j, -step, i, k_edge_t);
      vertical.push_back({static_cast<int>(k), i, std::min(a, b), std::max(a, b)});
    }
  }
  for (const Extension& h : horizontal)
    for (const Extension& v : vertical)
      if (h.from <= v.line && v.line <= h.to && v.from <= h.line && h.line <= v.to)
        return fmt::format(
            "the extension of T-junction vertex {} (row {}, columns {}..{}) meets that of vertex "
            "{} "
            "(column {}, rows {}..{})",
            h.vertex, h.line, h.from, h.to, v.vertex, v.line, v.from, v.to);
  return "";
}

void validate_tmesh(const TMesh& m, std::string_view origin) {
  for (const auto& [field, degree] : {std::pair{"degree_s", m.degree_s}, {"degree_t", m.degree_t}})
    if (degree < 1 || degree > kMaxDegree || degree % 2 == 0)
      fail(origin, m, field, std::to_string(degree),
           fmt::format("degree must be odd and in 1..{}", kMaxDegree));
  check_knot_lines(origin, m, "knots_s", m.knots_s);
  check_knot_lines(origin, m, "knots_t", m.knots_t);
  const int columns = static_cast<int>(m.knots_s.size());
  const int rows = static_cast<int>(m.knots_t.size());
  const std::size_t n = m.vertices.size();
  if (n < 1 || static_cast<std::int64_t>(n) > kMaxTSplineControlPoints)
    fail(origin, m, "vertices length", std::to_string(n),
         fmt::format("need 1 to {} vertices", kMaxTSplineControlPoints));
  if (m.points.size() != n)
    fail(origin, m, "points length", std::to_string(m.points.size()),
         fmt::format("need one point per vertex ({})", n));
  if (!m.weights.empty() && m.weights.size() != n)
    fail(origin, m, "weights length", std::to_string(m.weights.size()),
         fmt::format("need one weight per vertex ({}) or none", n));
  std::map<std::pair<int, int>, std::size_t> at;
  for (std::size_t k = 0; k < n; ++k) {
    const TMeshVertex& v = m.vertices[k];
    if (v.i < 0 || v.i >= columns || v.j < 0 || v.j >= rows)
      fail(origin, m, fmt::format("vertex {}", k), fmt::format("({}, {})", v.i, v.j),
           fmt::format("outside the index rectangle [0, {}] x [0, {}]", columns - 1, rows - 1));
    const auto [it, fresh] = at.emplace(std::pair{v.i, v.j}, k);
    if (!fresh)
      fail(origin, m, fmt::format("vertex {}", k), fmt::format("({}, {})", v.i, v.j),
           fmt::format("same index position as vertex {}", it->second));
  }
  std::vector<int> valence(n, 0);
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    const auto [a, b] = m.edges[e];
    for (int end : {a, b})
      if (end < 0 || static_cast<std::size_t>(end) >= n)
        fail(origin, m, fmt::format("edge {}", e), std::to_string(end),
             fmt::format("no such vertex (there are {})", n));
    const TMeshVertex &va = m.vertices[a], &vb = m.vertices[b];
    if ((va.i != vb.i) == (va.j != vb.j))
      fail(origin, m, fmt::format("edge {}", e), fmt::format("{} -> {}", a, b),
           "an edge joins two distinct vertices on one row or one column");
    ++valence[a];
    ++valence[b];
  }
  const EdgeLines lines = edge_lines(m);
  for (const auto& [key, k] : at) {
    const auto [i, j] = key;
    auto inside = [&](const Segments& segments, int line, int x) {
      const auto it = segments.find(line);
      if (it == segments.end()) return false;
      for (const auto& seg : it->second)
        if (seg[0] < x && x < seg[1]) return true;
      return false;
    };
    if (inside(lines.vertical, i, j) || inside(lines.horizontal, j, i))
      fail(origin, m, fmt::format("vertex {}", k), fmt::format("({}, {})", i, j),
           "lies inside an edge: split the edge at it");
    if (valence[k] < 2)
      fail(origin, m, fmt::format("vertex {}", k), fmt::format("({}, {})", i, j),
           fmt::format("on {} edge(s): every vertex needs at least two", valence[k]));
  }
  const std::pair<const char*, bool> sides[4] = {
      {"side j = 0", covers_range(lines.horizontal, 0, 0, columns - 1)},
      {"side j = last", covers_range(lines.horizontal, rows - 1, 0, columns - 1)},
      {"side i = 0", covers_range(lines.vertical, 0, 0, rows - 1)},
      {"side i = last", covers_range(lines.vertical, columns - 1, 0, rows - 1)}};
  for (const auto& [side, covered] : sides)
    if (!covered)
      fail(origin, m, side, "open", "the boundary of the index rectangle must be covered by edges");
}

TSplineSurface infer_tspline(const TMesh& m, std::string_view origin) {
  validate_tmesh(m, origin);
  const EdgeLines lines = edge_lines(m);
  TSplineSurface s;
  s.name = m.name;
  s.degree_u = m.degree_s;
  s.degree_v = m.degree_t;
  s.points = m.points;
  s.weights = m.weights.empty() ? std::vector<double>(m.points.size(), 1.0) : m.weights;
  const int hu = (m.degree_s + 1) / 2, hv = (m.degree_t + 1) / 2;
  s.knots_u.resize(m.vertices.size() * (m.degree_s + 2));
  s.knots_v.resize(m.vertices.size() * (m.degree_t + 2));
  for (std::size_t k = 0; k < m.vertices.size(); ++k) {
    const TMeshVertex& v = m.vertices[k];
    double* ku = s.knots_u.data() + k * (m.degree_s + 2);
    double* kv = s.knots_v.data() + k * (m.degree_t + 2);
    ku[hu] = m.knots_s[v.i];
    kv[hv] = m.knots_t[v.j];
    // Rays along a row meet vertical edges (constant s); along a column, horizontal ones.
    cast_ray(lines.vertical, m.knots_s, v.i, +1, v.j, hu, ku + hu + 1);
    cast_ray(lines.vertical, m.knots_s, v.i, -1, v.j, hu, ku + hu - 1);
    cast_ray(lines.horizontal, m.knots_t, v.j, +1, v.i, hv, kv + hv + 1);
    cast_ray(lines.horizontal, m.knots_t, v.j, -1, v.i, hv, kv + hv - 1);
  }
  const int su = (m.degree_s - 1) / 2, sv = (m.degree_t - 1) / 2;
  const int columns = static_cast<int>(m.knots_s.size());
  const int rows = static_cast<int>(m.knots_t.size());
  if (columns - 1 - su < su || rows - 1 - sv < sv)
    fail(origin, m, "knots_s/knots_t length", fmt::format("{} x {}", columns, rows),
         fmt::format("too few index lines for degree {} x {}: no domain", m.degree_s, m.degree_t));
  s.u_min = m.knots_s[su];
  s.u_max = m.knots_s[columns - 1 - su];
  s.v_min = m.knots_t[sv];
  s.v_max = m.knots_t[rows - 1 - sv];
  validate_tspline(s, origin);
  return s;
}

TMesh tensor_tmesh(const Surface& s) {
  TMesh m;
  m.name = s.name;
  m.degree_s = s.degree_u;
  m.degree_t = s.degree_v;
  for (int i = 0; i < s.count_u; ++i) m.knots_s.push_back(s.knots_u[i + (s.degree_u + 1) / 2]);
  for (int j = 0; j < s.count_v; ++j) m.knots_t.push_back(s.knots_v[j + (s.degree_v + 1) / 2]);
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) {
      m.vertices.push_back({i, j});
      m.points.push_back(s.point(i, j));
      m.weights.push_back(s.weight(i, j));
      const int k = i * s.count_v + j;
      if (i + 1 < s.count_u) m.edges.push_back({k, k + s.count_v});
      if (j + 1 < s.count_v) m.edges.push_back({k, k + 1});
    }
  return m;
}

TMesh with_column_segment(const TMesh& a, int column, double knot, int row) {
  TMesh b = a;
  b.knots_s.insert(b.knots_s.begin() + column + 1, knot);
  for (TMeshVertex& v : b.vertices)
    if (v.i > column) ++v.i;
  b.edges.clear();
  const int lower = static_cast<int>(b.vertices.size()), upper = lower + 1;
  b.vertices.push_back({column + 1, row});
  b.vertices.push_back({column + 1, row + 1});
  b.points.push_back({0, 0, 0});
  b.points.push_back({0, 0, 0});
  b.weights.push_back(1);
  b.weights.push_back(1);
  for (const auto& e : a.edges) {
    const TMeshVertex &p = a.vertices[e[0]], &q = a.vertices[e[1]];
    const bool cut = p.j == q.j && (p.j == row || p.j == row + 1) && std::min(p.i, q.i) == column &&
                     std::max(p.i, q.i) == column + 1;
    if (!cut) {
      b.edges.push_back(e);
      continue;
    }
    const int left = p.i < q.i ? e[0] : e[1], right = p.i < q.i ? e[1] : e[0];
    const int middle = p.j == row ? lower : upper;
    b.edges.push_back({left, middle});
    b.edges.push_back({middle, right});
  }
  b.edges.push_back({lower, upper});
  return b;
}

}  // namespace nurbs
