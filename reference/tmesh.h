// A T-mesh (Sederberg et al. 2003) in index space, and the inference of each control point's local
// knot vectors from it by 001's ray rule: from a vertex, cast a ray in each of the four directions;
// the knots it meets on perpendicular edges are the vertex's knots that way, up to the
// ((degree+1)/2)-th ("the second intersection" for bicubic).
//
// Index space: vertex k sits at integer (column i, row j); column i has knot value knots_s[i] and
// row j knots_t[j]. Knot intervals on edges (the 2003 paper's form) are the differences of
// consecutive knot values; a zero interval is a repeated knot (two index lines, one parameter).
// This form is used rather than per-edge intervals because the paper's consistency rule (opposite
// sides of a face sum to the same interval) then holds by construction.
//
// T-junctions need no special case: a T-junction's stem is an edge whose end touches the ray's
// line, so it is met; the missing edge is not. Faces are implied by the edges (every face is an
// index-space rectangle) and not stored.
//
// Boundary: the T-mesh is the index rectangle [0, knots_s.size()-1] x [0, knots_t.size()-1], its
// four sides covered by edges. A ray that leaves it before meeting enough edges takes the boundary
// line's knot for every missing one: the boundary is a knot line of full multiplicity beyond what
// the mesh shows. With (degree-1)/2 zero-interval lines along each side -- Rhino's
// force-bezier-end-conditions meshes, scenes/tsm -- that gives clamped (Bézier) ends: the corner
// control points are interpolated. The domain is the rectangle between the index lines
// (degree-1)/2 in from each side (for a tensor mesh: the NURBS domain [knots[p], knots[count]]).
//
// Analysis-suitability (Li, Zheng, Sederberg, Hughes, Scott 2012): no horizontal T-junction
// extension meets a vertical one. On such meshes the blending functions sum to one; elsewhere the
// rational form still defines the surface (Rhino's meshes need not be analysis-suitable).
#pragma once

#include <array>
#include <string>
#include <string_view>
#include <vector>

#include "reference/surface.h"
#include "reference/tspline.h"

namespace nurbs {

struct TMeshVertex {
  int i = 0;  // index column
  int j = 0;  // index row
};

struct TMesh {
  std::string name;
  int degree_s = 3;             // u
  int degree_t = 3;             // v
  std::vector<double> knots_s;  // knot value of each index column, non-decreasing
  std::vector<double> knots_t;  // of each index row
  std::vector<TMeshVertex> vertices;
  // Axis-aligned segments between two vertices, with no vertex strictly inside (split them).
  std::vector<std::array<int, 2>> edges;
  std::vector<Point3> points;   // one control point per vertex
  std::vector<double> weights;  // one per vertex (all 1 if empty)
};

// Throws InputError naming the mesh, the element (vertex/edge/column/row) and the value for the
// first violated rule: odd degrees, finite non-decreasing knots, vertices inside the index
// rectangle and distinct, edges between existing distinct vertices on one row or column with no
// vertex inside, the four sides covered by edges, every vertex on at least two edges, one point
// (and weight) per vertex.
void validate_tmesh(const TMesh& mesh, std::string_view origin);

// A T-junction is a vertex with exactly one of its four directions missing an edge (boundary
// vertices excepted: their missing direction points out of the mesh). Its extension is the closed
// index-space segment from the ((degree+1)/2)-th perpendicular edge met in the missing direction
// (face extension) to the ((degree-1)/2)-th met the opposite way (edge extension). Returns "" when
// analysis-suitable, else which two T-junctions' extensions meet. The mesh must be valid.
std::string analysis_suitability_violation(const TMesh& mesh);

// The full grid of a NURBS surface's control points: column i carries the middle knot of basis
// function i, knots_u[i + (p+1)/2], so the ray rule gives function i's knots knots_u[i .. i+p+1]
// wherever they are in the mesh, and the boundary rule repeats the end knot -- the NURBS surface
// exactly when its knot vectors are clamped (end multiplicity p+1) and its degrees odd.
TMesh tensor_tmesh(const Surface& nurbs);

// Mesh `mesh` with a new index column after column `column`, at knot value `knot`, carrying one
// edge from row `row` to row + 1; the two row edges it cuts are split, leaving two T-junctions
// (a face split, Sederberg et al. 2004). The new vertices are the last two, with the point
// (0, 0, 0) and weight 1 for the caller to set.
TMesh with_column_segment(const TMesh& mesh, int column, double knot, int row);

// The point-based T-spline of the mesh: point k = vertex k, its local knot vectors by the ray rule
// above, the domain as stated above. Validates the mesh first and the result after.
TSplineSurface infer_tspline(const TMesh& mesh, std::string_view origin);

}  // namespace nurbs
