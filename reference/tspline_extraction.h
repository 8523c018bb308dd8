// Bézier extraction of a T-spline (Scott, Borden, Verhoosel, Sederberg, Hughes, "Isogeometric
// finite element data structures based on Bézier extraction of T-splines", 2011): per element, the
// operator C_e with [blending functions restricted to e] = C_e . [Bernstein polynomials of e], and
// from it the element's rational Bézier patch.
//
// Elements are the cells of the influence index (reference/tspline.h): on each, every blending
// function is one tensor-product polynomial. C_e is the outer product of each function's
// univariate operators; a univariate row is the function's Bézier segment (A5.6 DecomposeCurve,
// reference/bezier_decomposition.h, run on the padded local knot vector with the unit coefficient
// on the function) cut down to the cell by de Casteljau subdivision when the cell is a strict part
// of the segment -- a cell can be, since other functions' knots subdivide it.
#pragma once

#include <vector>

#include "reference/surface.h"
#include "reference/tspline.h"

namespace nurbs {

struct BezierElement {
  int cell_u = 0, cell_v = 0;
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  std::vector<int> functions;  // control points with support on the element, ascending
  // C_e, row-major: row r (functions[r]) holds (degree_u+1)(degree_v+1) coefficients, Bernstein
  // (k, l) at k*(degree_v+1) + l.
  std::vector<long double> extraction;
};

struct TSplineExtraction {
  int degree_u = 0, degree_v = 0;
  std::vector<BezierElement> elements;  // cell (cu, cv) at cu * cells_v + cv
};

// The degree+1 Bernstein coefficients on [a, b] of the one basis function on `local` (degree+2
// knots); [a, b] must lie in one span of `local` (a cell of the influence index does).
void local_bernstein_coefficients(int degree, const double* local, double a, double b,
                                  long double* out);

TSplineExtraction extract_bezier_elements(const TSplineSurface& surface,
                                          const TSplineInfluence& index);

// The element's homogeneous Bézier control points, Q_kl = sum_r C_e[r][kl] w_r (P_r, 1), in
// extended precision: out[k * (degree_v+1) + l], (degree_u+1)(degree_v+1) of them.
void element_homogeneous_points(const TSplineSurface& surface, const TSplineExtraction& extraction,
                                const BezierElement& element, Vec4<long double>* out);

// Same degrees, domain and local knot vectors: an extraction of `a` still holds for `b` (only
// points or weights moved).
bool same_extraction_topology(const TSplineSurface& a, const TSplineSurface& b);

// The element's rational Bézier patch, Q_kl = sum_r C_e[r][kl] w_r (P_r, 1), as a NURBS surface
// with one clamped span per direction (rounded to double once).
Surface bezier_patch(const TSplineSurface& surface, const TSplineExtraction& extraction,
                     const BezierElement& element);

}  // namespace nurbs
