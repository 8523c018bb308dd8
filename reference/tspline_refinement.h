// Local refinement of a T-spline that provably keeps the surface: Sederberg, Cardon, Finnigan,
// North, Zheng, Lyche, "T-spline simplification and local refinement" (2004), section 3. Inserting
// a knot k (t_0 < k < t_{p+1}) into one blending function's local knot vector t splits it exactly
// (Boehm's knot insertion restricted to one function):
//   N[t](u) = c1 N[m_0 .. m_{p+1}](u) + c2 N[m_1 .. m_{p+2}](u),  m = t with k inserted,
//   c1 = (k - t_0) / (t_p - t_0) if k < t_p else 1,  c2 = (t_{p+1} - k) / (t_{p+1} - t_1) if k >
//   t_1 else 1,
// so the point's term w P N becomes (c1 w) P N1 + (c2 w) P N2; functions that end up with equal
// local knot vectors are then merged (their homogeneous coefficients w P, w add). A T-mesh
// refinement is a sequence of such splits whose pieces all land on the refined mesh's functions
// (the 2004 paper's "no violation" condition); the test checks that they do.
//
// The surface is kept exactly in real arithmetic; the new weights and points are rounded to
// double once per split and merge (the data model stores doubles).
#pragma once

#include <cstddef>

#include "reference/tspline.h"

namespace nurbs {

// Splits point `point`'s blending function at `knot` in u (or v): the point keeps the first piece,
// the second is appended as a new point. Throws std::invalid_argument if the knot is not strictly
// inside the function's support in that direction.
void split_blending_function_u(TSplineSurface& surface, std::size_t point, double knot);
void split_blending_function_v(TSplineSurface& surface, std::size_t point, double knot);

// Merges points whose local knot vectors are equal in both directions (first occurrence keeps its
// place): w = w_1 + w_2, P = (w_1 P_1 + w_2 P_2) / w, summed in long double.
void merge_equal_blending_functions(TSplineSurface& surface);

// The 2004 paper's refinement onto a finer T-mesh's functions: `fine` is the T-spline of a mesh
// that contains `coarse`'s (its first coarse.count() vertices are coarse's, in order, each gaining
// at most one knot per direction); every coarse function is split by the knots it gains, equal
// functions are merged, and the result is `fine` with those control points and weights -- the
// coarse surface on the fine T-mesh. Throws std::invalid_argument when the pieces do not land
// exactly on fine's functions (the paper's "violation": the refinement would change the surface).
TSplineSurface refine_onto(const TSplineSurface& coarse, const TSplineSurface& fine);

}  // namespace nurbs
