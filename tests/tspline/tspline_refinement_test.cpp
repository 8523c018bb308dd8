// Local refinement (reference/tspline_refinement.h) keeps the surface: a NURBS surface's tensor
// mesh refined by one new edge inside one face (two new vertices, two T-junctions) through
// Sederberg et al. 2004's blending-function splits gives exactly the refined mesh's blending
// functions, and the same surface.
#include "reference/tspline_refinement.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"
#include "tests/tspline/tspline_meshes.h"

namespace nurbs {
namespace {

using test::Rng;
using LD = long double;

// Mesh `a` with a new index column after column `c` at knot `k` carrying one vertical edge from
// row r to row r+1 (the horizontal edges it cuts are split): two T-junctions.
TMesh with_face_split(const TMesh& a, int c, double k, int r) {
  TMesh b = a;
  b.knots_s.insert(b.knots_s.begin() + c + 1, k);
  for (TMeshVertex& v : b.vertices)
    if (v.i > c) ++v.i;
  b.edges.clear();
  const int lower = static_cast<int>(b.vertices.size()), upper = lower + 1;
  b.vertices.push_back({c + 1, r});
  b.vertices.push_back({c + 1, r + 1});
  b.points.push_back({0, 0, 0});  // filled by the refinement in the test
  b.points.push_back({0, 0, 0});
  b.weights.push_back(1);
  b.weights.push_back(1);
  for (const auto& e : a.edges) {
    const TMeshVertex &p = a.vertices[e[0]], &q = a.vertices[e[1]];
    const bool cut = p.j == q.j && (p.j == r || p.j == r + 1) && std::min(p.i, q.i) == c &&
                     std::max(p.i, q.i) == c + 1;
    if (!cut) {
      b.edges.push_back(e);
      continue;
    }
    const int left = p.i < q.i ? e[0] : e[1], right = p.i < q.i ? e[1] : e[0];
    const int middle = p.j == r ? lower : upper;
    b.edges.push_back({left, middle});
    b.edges.push_back({middle, right});
  }
  b.edges.push_back({lower, upper});
  return b;
}

std::vector<double> knot_key(const TSplineSurface& s, std::size_t k) {
  std::vector<double> key(s.local_knots_u(k), s.local_knots_u(k) + s.degree_u + 2);
  key.insert(key.end(), s.local_knots_v(k), s.local_knots_v(k) + s.degree_v + 2);
  return key;
}

TEST(TSplineRefinement, FaceSplitKeepsTheSurface) {
  Rng rng(2004);
  test::Worst worst("max |S_refined - S_original| / scale");
  int refined_meshes = 0;
  for (const auto& [p, q] : {std::pair{3, 3}, {1, 3}, {5, 3}, {3, 1}}) {
    for (int trial = 0; trial < 4; ++trial) {
      const int cu = p + 4, cv = q + 4;
      const Surface nurbs = test::random_surface(rng, p, q, cu, cv, test::Ends::clamped, true, 1);
      const TMesh mesh_a = test::tensor_tmesh(nurbs);
      // A face away from the boundary's repeated lines, split at a knot strictly inside it.
      const int c = test::uniform_int(rng, (p - 1) / 2 + 1, cu - 2 - (p - 1) / 2 - 1);
      const int r = test::uniform_int(rng, (q - 1) / 2, cv - 2 - (q - 1) / 2);
      const double lo = mesh_a.knots_s[c], hi = mesh_a.knots_s[c + 1];
      if (!(lo < hi)) continue;
      const double k = lo + (hi - lo) * 0.375;
      const TMesh mesh_b = with_face_split(mesh_a, c, k, r);
      ASSERT_EQ(analysis_suitability_violation(mesh_b), "");
      const TSplineSurface a = infer_tspline(mesh_a, "a");
      const TSplineSurface b = infer_tspline(mesh_b, "b");

      // Split every function of `a` by the knots its vertex gains in `b` (vertex k of a is vertex
      // k of b), then merge equal functions.
      TSplineSurface refined = a;
      for (std::size_t v = 0; v < a.count(); ++v) {
        const double* old_u = a.local_knots_u(v);
        const double* new_u = b.local_knots_u(v);
        std::vector<double> gained;
        std::set_difference(new_u, new_u + p + 2, old_u, old_u + p + 2, std::back_inserter(gained));
        ASSERT_TRUE(std::equal(a.local_knots_v(v), a.local_knots_v(v) + q + 2, b.local_knots_v(v)));
        ASSERT_LE(gained.size(), 1u);
        if (!gained.empty()) split_blending_function_u(refined, v, gained[0]);
      }
      merge_equal_blending_functions(refined);

      // The refined functions are exactly b's: same knot vectors, one each.
      ASSERT_EQ(refined.count(), b.count());
      std::vector<std::vector<double>> keys_refined, keys_b;
      for (std::size_t v = 0; v < b.count(); ++v) {
        keys_refined.push_back(knot_key(refined, v));
        keys_b.push_back(knot_key(b, v));
      }
      std::sort(keys_refined.begin(), keys_refined.end());
      std::sort(keys_b.begin(), keys_b.end());
      ASSERT_EQ(keys_refined, keys_b);

      // b with the refined control points is the original surface.
      TSplineSurface b_points = b;
      for (std::size_t v = 0; v < b.count(); ++v)
        for (std::size_t w = 0; w < refined.count(); ++w)
          if (knot_key(refined, w) == knot_key(b, v)) {
            b_points.points[v] = refined.points[w];
            b_points.weights[v] = refined.weights[w];
          }
      validate_tspline(b_points, "refined");
      const TSplineInfluence index_a(a, "a"), index_b(b_points, "b");
      const LD scale = 8;  // random_surface points lie in [-8, 8]^3
      for (const auto& [u, v] :
           test::domain_samples(rng, b_points, index_b.breaks_u(), index_b.breaks_v(), 100)) {
        const auto before = evaluate_tspline(a, index_a, u, v, 0);
        const auto after = evaluate_tspline(b_points, index_b, u, v, 0);
        const LD error =
            std::hypot(after.point[0] - before.point[0], after.point[1] - before.point[1],
                       after.point[2] - before.point[2]) /
            scale;
        worst.update(double(error), [&] { return fmt::format("{}x{} ({}, {})", p, q, u, v); });
        // Weights and points were rounded to double once per split and merge.
        ASSERT_LE(error, 1e-14L) << p << "x" << q << " (" << u << ", " << v << ")";
      }
      ++refined_meshes;
    }
  }
  EXPECT_EQ(refined_meshes, 16);
}

// The split itself is exact in real arithmetic: the two pieces sum to the original function.
TEST(TSplineRefinement, SplitPiecesSumToTheFunction) {
  TSplineSurface s;
  s.name = "one";
  s.degree_u = 3;
  s.degree_v = 1;
  s.points = {{1, 2, 3}};
  s.weights = {0.75};
  s.knots_u = {0, 1, 3, 4, 8};
  s.knots_v = {0, 1, 2};
  s.u_min = 0;
  s.u_max = 8;
  s.v_min = 0;
  s.v_max = 2;
  for (const double knot : {0.5, 1.0, 2.0, 3.5, 6.0}) {
    TSplineSurface t = s;
    split_blending_function_u(t, 0, knot);
    ASSERT_EQ(t.count(), 2u);
    for (int a = 0; a <= 64; ++a) {
      const double u = a / 8.0, v = 0.75;
      auto weighted = [&](const TSplineSurface& x) {
        LD sum = 0;
        for (std::size_t k = 0; k < x.count(); ++k) {
          const int su = local_span(3, x.local_knots_u(k), u, u == 8.0);
          const int sv = local_span(1, x.local_knots_v(k), v, false);
          if (su < 0 || sv < 0) continue;
          LD nu[3], nv[3];
          local_basis(3, x.local_knots_u(k), su, LD(u), 0, nu);
          local_basis(1, x.local_knots_v(k), sv, LD(v), 0, nv);
          sum += x.weights[k] * nu[0] * nv[0];
        }
        return sum;
      };
      ASSERT_LE(std::fabs(weighted(t) - weighted(s)), 1e-15L) << "knot " << knot << " u " << u;
    }
  }
  EXPECT_THROW(split_blending_function_u(s, 0, 8.0), std::invalid_argument);
}

}  // namespace
}  // namespace nurbs
