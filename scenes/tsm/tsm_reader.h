// Reader of the Rhino T-Splines plug-in's text format (`#TS0200`, the .tsm files of GrapeTec/
// T-SPLINE's rhino/ folder) into a T-mesh (reference/tmesh.h) in index space.
//
// What the format is, as inferred from the six sample files and from the record layout GrapeTec's
// LGPL reader parses (source/rhparser.cpp, rhspreader.cpp; read, not copied). Sure = checked on
// the files; likely = consistent with every file but not independently confirmed.
// - Header (sure): `#TS0200`, then `degree N`, `cap-type`, `star-smoothness`, `units V NAME`,
//   `force-bezier-end-conditions 0|1`. `#` starts a comment (mouse.tsm has non-ASCII comments,
//   CRLF line ends). A record type with nothing after it is a deleted slot: it keeps its index.
// - `f LINK FLAG`: a face and one half-edge of its loop. `e LINK INTERVAL`: an edge, one of its
//   half-edges and its knot interval. `v LINK DIRECTION`: a vertex, one outgoing half-edge and that
//   half-edge's compass direction in the vertex's own frame (sure: the layouts below only decode
//   with it). `l PREV NEXT OPP VERTEX FACE EDGE FLAG`: a half-edge leaving VERTEX, in face FACE
//   (-1 outside the surface); FLAG 0 = the face turns a corner at VERTEX, non-zero = VERTEX lies
//   inside the face's side (a T-junction or a straight boundary point). Face loops run
//   counter-clockwise in (s, t) (sure on simple.tsm, whose control net shows the layout).
// - `0g X Y Z W`: control points, in the order of the grip records `0m gvp VERTEX` (the vertex's
//   own point) / `0m gv VERTEX` (an extra point of that vertex; -1 with an empty `0g` = deleted).
//   X Y Z are taken as Cartesian, not pre-multiplied by W (likely: GrapeTec's evaluator,
//   BlendingEquation::computePoint, sums w N (X, Y, Z) / sum w N over these values; the files
//   cannot tell, all but two having W = 1 and Bike.tsm, face.tsm W within 2e-4 of 1).
// - `0m cg VERTEX VALENCE D0..D3 GRIP...`: a vertex carrying extra control points on D_k repeated
//   (zero-interval) knot lines toward compass direction k of its frame (N, W, S, E for k = 0..3);
//   the grips fill the wedges k = 0..3 in order, wedge k stepping 1..D_k along direction k (outer)
//   and 0..D_{k+1} along direction k+1 (inner) (sure on simple.tsm: 16 of 16 extra points land
//   on their coordinates). This is how force-bezier-end-conditions makes clamped ends: each
//   boundary vertex gets (degree-1)/2 lines inside the boundary.
// - `ec`, `tol`, `ver`, `0m odd-grip-map`, and the `100001uv`, `100001uvr`, `50000grip`, `105...`
//   records: not needed for the surface and skipped; an `ec EDGE C` with C != 0 (never seen) is
//   refused since its meaning (a crease?) is unknown.
//
// Refused with a reason (InputError, the CLI's exit 2): an extraordinary (star) point -- an
// interior vertex whose face corners do not add up to 360 degrees -- named with its line; a
// boundary vertex with a concave corner, or faces that do not tile their bounding rectangle (a
// hole): only rectangular domains are supported; knot intervals that do not close up (a closed
// or inconsistent mesh); any malformed record (file, line, field, value).
//
// The six samples: simple.tsm (analysis-suitable), fan.tsm and gearbox2-9.tsm import; mouse.tsm
// and Bike.tsm have one boundary loop with two concave corners (notched domains), face.tsm three
// boundary loops (two holes, 8 concave corners). None has an interior star point (every interior
// vertex's face corners add up to 360 degrees). gearbox2-9.tsm is not
// analysis-suitable and its blending functions do not sum to one (the rational form still
// defines it); whether Rhino evaluates it the same way could not be checked here.
#pragma once

#include <string>
#include <string_view>

#include "reference/tmesh.h"

namespace nurbs {

// `origin` (the path) prefixes every error: "<origin>:<line>: <record> <field> = <value>: <rule>".
TMesh parse_tsm(std::string_view bytes, const std::string& origin);
TMesh load_tsm_file(const std::string& path);

}  // namespace nurbs
