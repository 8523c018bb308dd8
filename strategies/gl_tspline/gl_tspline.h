// gl-tspline: Krishnamurthy & Yasui (001), T-spline evaluation on OpenGL, with the fragment
// program split into passes as 001 proposes ("splitting the fragment program into smaller pieces
// and then execute each individual part sequentially") after their card's instruction limit
// stopped the single program. CPU (prepare): the influence index of 001 Fig 7 (region = cell of
// the knot-line grid), each sample's region by binary search, and textures of the homogeneous
// control points, their local knot vectors, the per-region active lists (CSR) and the per-sample
// (u, v, region). GPU (evaluate): ceil(max active points per region / points per pass)
// accumulation passes over one fragment per sample, each adding its share of the region's
// blending functions (Cox-de Boor on each point's local knots) times w P to ping-ponged float
// sums (with the derivative sums for normals), then one divide pass. T-splines only, odd degrees,
// float32, grid / span-grid / explicit samples, normals; deforming frames re-upload the points
// only.
//
// Where 001 is silent or ambiguous, and what is done here:
// - Regions: 001 splits the T-mesh's faces by the knot values crossing them (Fig 7); here a region
//   is a cell of the grid of every distinct knot value (TSplineInfluence), a refinement that needs
//   only the point-based form. Each region's list also carries, per point, the span of its local
//   knot vectors covering the region (region_tables.h says why).
// - The split: 001 says only "smaller pieces". Its NURBS path computes the u and v basis into
//   textures first (steps 2a, 2b) and accumulates k_u x k_v passes; a T-spline point has its own
//   knots, so a basis texture would be per sample and point. Here one piece = a number of the
//   region's active points: each pass computes their N[u_k](u) N[v_k](v) (Cox-de Boor, eq. 2, on
//   the local knots) and accumulates, so the program's size is set by points per pass, and 1
//   point per pass is the smallest program (the finest split).
// - Accumulation: ping-pong between two float targets, as 001's NURBS passes (tex1/tex2).
// - Degree: eq. 5 is cubic; any odd degree is evaluated (arrays sized per compiled degree pair).
// - Normals: 001 evaluates points only; the derivative sums and the quotient rule are added.
//
// Options (StrategyOptions.extra): "gl" = osmesa | egl (default egl);
// "tspline-points-per-pass" = N active points per accumulation pass (default 16, a bicubic
// region of a tensor mesh in one pass; 1 = the finest split). Record details: "passes" (draws
// the last evaluate() issued), "accumulation_passes", "points_per_pass", "max_active_points",
// "regions".
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyDescriptor gl_tspline_descriptor();
StrategyEntry gl_tspline_entry();

}  // namespace nurbs
