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
      const TMesh mesh_b = with_column_segment(mesh_a, c, k, r);
      ASSERT_EQ(analysis_suitability_violation(mesh_b), "");
      const TSplineSurface a = infer_tspline(mesh_a, "a");
      const TSplineSurface b = infer_tspline(mesh_b, "b");
      // Every function of `a` split by the knots its vertex gains in `b` (vertex k of a is vertex
      // k of b), equal functions merged: exactly b's functions, or refine_onto throws.
      const TSplineSurface b_points = refine_onto(a, b);
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

// refine_onto refuses a finer T-spline whose functions are not pieces of the coarse ones.
TEST(TSplineRefinement, RefineOntoRefusesWhatIsNoRefinement) {
  Rng rng(7);
  const Surface nurbs = test::random_surface(rng, 3, 3, 7, 7, test::Ends::clamped, true, 1);
  const TMesh mesh_a = tensor_tmesh(nurbs);
  const TSplineSurface a = infer_tspline(mesh_a, "a");
  const TMesh mesh_b =
      with_column_segment(mesh_a, 2, 0.5 * (mesh_a.knots_s[2] + mesh_a.knots_s[3]), 2);
  const TSplineSurface b = infer_tspline(mesh_b, "b");
  EXPECT_NO_THROW(refine_onto(a, b));
  // Identity: nothing gained, the same surface.
  const TSplineSurface same = refine_onto(a, a);
  EXPECT_EQ(same.points, a.points);
  // A new function's knot moved: no split of a's functions gives it.
  TSplineSurface moved = b;
  moved.knots_v[(b.count() - 1) * 5 + 4] += 0.125;
  EXPECT_THROW(refine_onto(a, moved), std::invalid_argument);
  // Coarser than the coarse one.
  EXPECT_THROW(refine_onto(b, a), std::invalid_argument);
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
