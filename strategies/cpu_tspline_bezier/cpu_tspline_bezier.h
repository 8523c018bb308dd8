// cpu-tspline-bezier: a T-spline (001) through its Bézier extraction (Scott, Borden, Verhoosel,
// Sederberg, Hughes 2011; reference/tspline_extraction.h) on the CPU with cpu-tensor's kernels --
// the fast CPU T-spline path (issue 30), the counterpart of cpu-tspline as cpu-tensor is of
// cpu-coxdeboor.
//
// prepare(): the influence index and the extraction once per topology, then every element's
// homogeneous rational Bézier patch (in long double, rounded once to the request's precision),
// laid out as one net of cells_u (p+1) rows by cells_v (q+1) columns: element (cu, cv)'s point
// (k, l) at row cu (p+1) + k, column cv (q+1) + l. The elements are the influence index's cells,
// a grid, so that net is a tensor-product net whose "spans" are the elements: cpu-tensor's u
// contraction (tensor::contract_rows over the p+1 rows of the sample's element row) gives the
// iso-curve's (q+1) points per element column, and its v kernel (tensor::evaluate_row, runs of v
// samples in one element column) finishes the row, SIMD across samples, OpenMP across rows.
//
// evaluate(): per u and v sample, its element by the reference's rule (TSplineInfluence::cell_u/v:
// breaks[c] <= u < breaks[c+1], the domain end in the last cell) and its Bernstein basis (and
// first derivatives) at the element-local parameter (u - u0) / (u1 - u0) computed in long double
// and rounded once (cl-tspline-bezier's reason: a parameter rounded to float before the
// subtraction costs ulp(u) |S_u|); then the rows. Explicit lists: the same per sample, no tables.
//
// The elements are reference/tspline_extraction's, unchanged: the cells of the grid of every
// distinct local knot value (finer than 001's T-mesh faces, so one face's polynomial may span
// several elements; extraction cuts each function's Bézier segment to the cell by de Casteljau).
// Every element has the surface's degrees (a T-spline has one pair; even degrees are refused by
// the reference's validation), so no element needs a kernel of its own; a sample on a break
// shared by two elements belongs to the upper one, the domain end to the last, as in the
// reference. Normals where Su x Sv is rounding noise are zero: the T-spline
// reference's rule (reference/tspline.h, no limit normals), not cpu-tensor's NURBS limit normal.
// T-spline scenes only (NURBS: cpu-tensor). update_control_points() keeps the index and the
// extraction operators and rebuilds the nets.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry cpu_tspline_bezier_entry();

}  // namespace nurbs
