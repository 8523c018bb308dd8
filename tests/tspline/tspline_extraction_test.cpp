// Bézier extraction (reference/tspline_extraction.h) against independent evaluations:
// - C_e times the element's Bernstein polynomials reproduces every blending function there;
// - each rational Bézier patch, evaluated by the NURBS reference, is the T-spline there;
// - on a tensor mesh the patches are the NURBS surface's own Bézier decomposition (A5.7).
#include "reference/tspline_extraction.h"

#include <gtest/gtest.h>

#include <cmath>

#include "reference/bezier_decomposition.h"
#include "reference/nurbs_math.h"
#include "reference/tmesh.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "scenes/tsm/tsm_reader.h"
#include "tests/reference/random_nurbs.h"
#include "tests/reference/test_support.h"
#include "tests/tspline/tspline_meshes.h"

namespace nurbs {
namespace {

using test::Rng;
using LD = long double;

// Bernstein polynomials of degree p on [a, b] at t: A2.2 on the clamped single-span knot vector.
void bernstein(int degree, double a, double b, LD t, LD* out) {
  std::vector<LD> knots(degree + 1, LD(a));
  knots.insert(knots.end(), degree + 1, LD(b));
  basis_functions(degree, t, degree, knots.data(), out);
}

// A T-spline with its influence index and extraction.
struct Extracted {
  explicit Extracted(TSplineSurface s)
      : surface(std::move(s)),
        index(surface, surface.name),
        extraction(extract_bezier_elements(surface, index)) {}
  TSplineSurface surface;
  TSplineInfluence index;
  TSplineExtraction extraction;
};

// Random analysis-suitable meshes of several degrees (cells cut functions' spans where columns
// stop) and simple.tsm.
std::vector<Extracted> test_surfaces(Rng& rng) {
  std::vector<Extracted> out;
  for (const TMesh& mesh :
       test::random_vertical_tmeshes(rng, {{3, 3}, {1, 3}, {5, 3}, {3, 5}}, 4, true))
    out.emplace_back(infer_tspline(mesh, "test"));
  out.emplace_back(infer_tspline(
      load_tsm_file(std::string(NURBSBENCH_SOURCE_DIR) + "/scenes/data/tsplines/simple.tsm"),
      "simple.tsm"));
  return out;
}

TEST(TSplineExtraction, OperatorTimesBernsteinIsTheBlendingFunctions) {
  Rng rng(2011);
  test::Worst worst("max |C_e B - N|");
  for (const Extracted& t : test_surfaces(rng)) {
    const TSplineSurface& s = t.surface;
    const TSplineExtraction& x = t.extraction;
    const int p = s.degree_u, q = s.degree_v;
    for (const BezierElement& e : x.elements)
      for (int sample = 0; sample < 4; ++sample) {
        const double u = test::uniform_real(rng, e.u0, e.u1);
        const double v = test::uniform_real(rng, e.v0, e.v1);
        LD bu[kMaxOrder], bv[kMaxOrder];
        bernstein(p, e.u0, e.u1, u, bu);
        bernstein(q, e.v0, e.v1, v, bv);
        for (std::size_t r = 0; r < e.functions.size(); ++r) {
          const int k = e.functions[r];
          LD extracted = 0;
          for (int a = 0; a <= p; ++a)
            for (int b = 0; b <= q; ++b)
              extracted += e.extraction[(r * (p + 1) + a) * (q + 1) + b] * bu[a] * bv[b];
          LD nu[3], nv[3];
          local_basis(p, s.local_knots_u(k), local_span(p, s.local_knots_u(k), u, false), LD(u), 0,
                      nu);
          local_basis(q, s.local_knots_v(k), local_span(q, s.local_knots_v(k), v, false), LD(v), 0,
                      nv);
          const LD error = std::fabs(extracted - nu[0] * nv[0]);
          worst.update(double(error), [&] { return fmt::format("{} ({}, {})", s.name, u, v); });
          ASSERT_LE(error, 256 * scalar_epsilon<LD>()) << s.name << " point " << k;
        }
      }
  }
}

// The patch's control points are rounded to double once (the Surface data model), so agreement
// is to a few double ulps of the coordinates (8 in the random meshes, 30 in simple.tsm).
TEST(TSplineExtraction, PatchesReproduceTheDirectEvaluation) {
  Rng rng(2012);
  test::Worst worst("max |S_patch - S_tspline| / scale");
  for (const Extracted& t : test_surfaces(rng)) {
    const TSplineSurface& s = t.surface;
    const TSplineExtraction& x = t.extraction;
    double scale = 0;
    for (const Point3& p : s.points)
      for (double c : p) scale = std::max(scale, std::fabs(c));
    for (const BezierElement& e : x.elements) {
      const Surface patch = bezier_patch(s, x, e);
      validate_surface(patch, 0, "patch");
      const SurfaceNet<LD> net(patch);
      for (const double fu : {0.0, 0.3, 1.0})
        for (const double fv : {0.0, 0.6, 1.0}) {
          const double u = e.u0 + (e.u1 - e.u0) * fu, v = e.v0 + (e.v1 - e.v0) * fv;
          // Inside the element its polynomial, also on its closed edges: the brute force would
          // switch to the neighbour's span at an edge, which for C^0 knots has other derivatives
          // but the same point, so points are compared with it.
          const Vec3<LD> a = surface_point(net, LD(u), LD(v));
          const TSplineEvaluation<LD> b = evaluate_tspline_brute_force(s, u, v, 0);
          const LD error = std::hypot(a[0] - b.point[0], a[1] - b.point[1], a[2] - b.point[2]);
          worst.update(double(error / scale),
                       [&] { return fmt::format("{} ({}, {})", s.name, u, v); });
          ASSERT_LE(error, 1e-13L * scale) << s.name << " (" << u << ", " << v << ")";
        }
    }
  }
}

TEST(TSplineExtraction, TensorMeshPatchesAreTheNurbsDecomposition) {
  Rng rng(2013);
  for (const auto& [p, q] : {std::pair{3, 3}, {1, 3}, {5, 5}}) {
    const Surface nurbs = test::random_surface(rng, p, q, p + 4, q + 3, test::Ends::clamped, true,
                                               /*max_interior=*/1);
    const TSplineSurface s = infer_tspline(test::tensor_tmesh(nurbs), "test");
    const TSplineInfluence index(s, "test");
    const TSplineExtraction x = extract_bezier_elements(s, index);
    const BezierPatches<LD> decomposition = decompose_surface(SurfaceNet<LD>(nurbs));
    ASSERT_EQ(x.elements.size(), decomposition.patch_count());
    for (const BezierElement& e : x.elements) {
      const Surface patch = bezier_patch(s, x, e);
      const Vec4<LD>* expected = decomposition.patch(e.cell_u, e.cell_v);
      for (std::size_t j = 0; j < patch.points.size(); ++j) {
        const LD w = expected[j][3];
        ASSERT_LE(std::fabs(patch.weights[j] - w), 1e-15L * w)
            << "element " << e.cell_u << "," << e.cell_v;
        for (int c = 0; c < 3; ++c)
          ASSERT_LE(std::fabs(patch.points[j][c] - expected[j][c] / w), 1e-14L)
              << "element " << e.cell_u << "," << e.cell_v << " point " << j;
      }
    }
  }
}

}  // namespace
}  // namespace nurbs
