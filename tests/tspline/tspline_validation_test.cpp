// Malformed T-splines and T-meshes are InputErrors (the CLI's exit 2) whose one line names the
// surface or mesh, the point/vertex/edge, the field and index, and the value.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "tests/reference/random_nurbs.h"
#include "tests/tspline/tspline_meshes.h"

namespace nurbs {
namespace {

TSplineSurface valid_surface() {
  test::Rng rng(1);
  return infer_tspline(test::random_vertical_tmesh(rng, 3, 3, 7, 6, true), "test");
}

void expect_error(const std::function<void()>& action, const std::string& expected) {
  try {
    action();
    ADD_FAILURE() << "accepted; expected: " << expected;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(TSplineValidation, SurfaceErrorsNameThePointFieldIndexAndValue) {
  const TSplineSurface good = valid_surface();
  validate_tspline(good, "file.json");
  struct Case {
    std::function<void(TSplineSurface&)> damage;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {[](TSplineSurface& s) { s.knots_u[17 * 5 + 2] = NAN; },
       "file.json: tspline 'random-t': point 17 knots_u[2] = nan: knots must be finite"},
      {[](TSplineSurface& s) { s.knots_v[3 * 5 + 4] = s.knots_v[3 * 5 + 3] - 1; },
       "point 3 knots_v[4] = "},
      {[](TSplineSurface& s) { std::fill_n(s.knots_u.begin() + 5, 5, 0.25); },
       "point 1 knots_u[4] = 0.25: empty support"},
      {[](TSplineSurface& s) { s.weights[2] = 0; },
       "point 2 weight = 0: weights must be finite and > 0"},
      {[](TSplineSurface& s) { s.points[4][1] = INFINITY; }, "point 4 xyz[1] = inf"},
      {[](TSplineSurface& s) { s.degree_u = 2; }, "degree_u = 2: degree must be odd"},
      {[](TSplineSurface& s) { s.knots_v.pop_back(); }, "knots_v length = "},
      {[](TSplineSurface& s) { s.weights.pop_back(); }, "weights length = "},
      {[](TSplineSurface& s) { s.u_max = s.u_min; }, "u_max = "},
      {[](TSplineSurface& s) { s.v_min = NAN; }, "v_min = nan: the domain must be finite"},
      {[](TSplineSurface& s) { s.points.clear(); }, "points length = 0"},
  };
  for (const Case& c : cases) {
    TSplineSurface s = good;
    c.damage(s);
    expect_error([&] { validate_tspline(s, "file.json"); }, c.expected);
  }
}

TEST(TSplineValidation, MeshErrorsNameTheElement) {
  test::Rng rng(2);
  const TMesh good = test::random_vertical_tmesh(rng, 3, 3, 6, 6, false);
  validate_tmesh(good, "mesh");
  struct Case {
    std::function<void(TMesh&)> damage;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {[](TMesh& m) { m.edges[3][1] = 999; }, "tmesh 'random-t': edge 3 = 999: no such vertex"},
      {[](TMesh& m) {
         m.edges.push_back({0, static_cast<int>(m.vertices.size()) - 1});
       },
       "one row or one column"},
      {[](TMesh& m) { m.vertices[1] = m.vertices[0]; }, "same index position as vertex 0"},
      {[](TMesh& m) { m.vertices[0].i = -1; }, "vertex 0 = (-1, 0): outside the index rectangle"},
      {[](TMesh& m) { m.knots_s[2] = NAN; }, "knots_s[2] = nan: knots must be finite"},
      {[](TMesh& m) { m.knots_t[3] = m.knots_t[2] - 1; }, "knots_t[3] = "},
      {[](TMesh& m) { m.degree_t = 4; }, "degree_t = 4: degree must be odd"},
      {[](TMesh& m) { m.points.pop_back(); }, "points length = "},
      // Dropping the boundary edges of row 0 opens the boundary (and strands its vertices).
      {[](TMesh& m) {
         std::erase_if(m.edges, [&](const std::array<int, 2>& e) {
           return m.vertices[e[0]].j == 0 && m.vertices[e[1]].j == 0;
         });
       },
       "vertex 0 = (0, 0): on 1 edge(s)"},
  };
  for (const Case& c : cases) {
    TMesh m = good;
    c.damage(m);
    expect_error([&] { infer_tspline(m, "mesh"); }, c.expected);
  }
  // An edge that runs over a vertex must be split there.
  TMesh skipping = good;
  const auto& e0 = skipping.edges[0];
  const int a = e0[0], b = e0[1];
  int c = -1;
  for (const auto& e : skipping.edges)
    if (e[0] == b && skipping.vertices[e[1]].j == skipping.vertices[a].j) c = e[1];
  ASSERT_GE(c, 0);
  skipping.edges.push_back({a, c});
  expect_error([&] { validate_tmesh(skipping, "mesh"); }, "lies inside an edge");
}

// A 7x7 bicubic grid with the vertical edge (3,3)-(3,4) and the horizontal edge (3,2)-(4,2)
// removed: the first leaves T-junctions (3,3), (3,4) whose extensions run along column 3 over rows
// 2..5 (face extension: two crossings toward the missing edge; edge extension: one the other way),
// the second T-junctions (3,2), (4,2) with extensions along row 2 over columns 2..5 (from (3,2))
// and 2..5 (from (4,2)): they meet at (3, 2), so the mesh is not analysis-suitable. Without the
// second removal it is.
TEST(TSplineValidation, AnalysisSuitabilityFindsMeetingExtensions) {
  TMesh m;
  m.name = "grid";
  for (int k = 0; k < 7; ++k) {
    m.knots_s.push_back(k < 2 ? 0 : k > 4 ? 4 : k - 1);
    m.knots_t.push_back(k < 2 ? 0 : k > 4 ? 4 : k - 1);
  }
  for (int i = 0; i < 7; ++i)
    for (int j = 0; j < 7; ++j) {
      m.vertices.push_back({i, j});
      m.points.push_back({double(i), double(j), 0});
    }
  auto id = [](int i, int j) { return i * 7 + j; };
  auto grid_without = [&](std::vector<std::array<int, 2>> removed) {
    TMesh out = m;
    for (int i = 0; i < 7; ++i)
      for (int j = 0; j < 7; ++j) {
        const std::array<int, 2> right{id(i, j), id(i + 1, j)}, up{id(i, j), id(i, j + 1)};
        if (i + 1 < 7 && std::find(removed.begin(), removed.end(), right) == removed.end())
          out.edges.push_back(right);
        if (j + 1 < 7 && std::find(removed.begin(), removed.end(), up) == removed.end())
          out.edges.push_back(up);
      }
    return out;
  };
  const TMesh vertical_only = grid_without({{id(3, 3), id(3, 4)}});
  EXPECT_EQ(analysis_suitability_violation(vertical_only), "");
  const TMesh both = grid_without({{id(3, 3), id(3, 4)}, {id(3, 2), id(4, 2)}});
  const std::string violation = analysis_suitability_violation(both);
  EXPECT_NE(violation.find("row 2, columns 2..5"), std::string::npos) << violation;
  EXPECT_NE(violation.find("column 3, rows 2..5"), std::string::npos) << violation;
}

TEST(TSplineValidation, InfluenceIndexRefusesTooManyRegions) {
  TSplineSurface s;
  s.name = "wide";
  s.degree_u = s.degree_v = 1;
  // 2100 x 2100 distinct knots: over kMaxTSplineRegions cells.
  for (int k = 0; k < 2100; ++k) {
    s.points.push_back({0, 0, 0});
    s.weights.push_back(1);
    s.knots_u.insert(s.knots_u.end(), {double(k), k + 0.5, k + 1.0});
    s.knots_v.insert(s.knots_v.end(), {double(k), k + 0.25, k + 1.0});
  }
  s.u_min = s.v_min = 0;
  s.u_max = s.v_max = 2100;
  validate_tspline(s, "wide");
  expect_error([&] { TSplineInfluence index(s, "wide"); }, "regions exceed the limit");
}

}  // namespace
}  // namespace nurbs
