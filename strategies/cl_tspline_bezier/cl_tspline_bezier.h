// cl-tspline-bezier: a T-spline (001) evaluated through its Bézier extraction (Scott, Borden,
// Verhoosel, Sederberg, Hughes 2011; reference/tspline_extraction.h) on OpenCL -- the T-spline
// issue's "extracted-Bézier path", so the Bézier machinery of the GPU paths evaluates T-splines.
//
// prepare() (timed as upload) builds the influence index and the extraction ONCE per topology and
// uploads, per element (= influence cell), the extraction operator C_e in the request's precision,
// the element's active control points (CSR), the control points (P, w) and the cell breaks (the
// elements form a grid, so the breaks are the element bounds). A first kernel, decompose_elements,
// forms every element's rational Bézier patch Q = C_e^T (w P, w) on the device, relative to the
// element's first control point (tspline_bezier.cl says why); evaluate() runs only
// evaluate_samples, one work-item per sample (Bernstein polynomials, normals from the first
// derivatives). update_control_points() re-sends the control points and reruns decompose_elements:
// the operators, CSR lists and parameters stay (they are topology).
//
// Each sample's element and element-local parameter are found on the host in prepare(), in
// double, by the reference's own rule (TSplineInfluence::cell_u/v: breaks[c] <= u < breaks[c+1],
// the domain end in the last cell); the kernel gets (cell, (u - breaks[c]) / width) rounded once
// to its precision. A search in the kernel would compare float-rounded parameters with
// float-rounded breaks and could pick the neighbour of the reference's cell at a break; and a
// parameter rounded to float before the subtraction costs ulp(u) |S_u|, which grows with the
// domain's offset (a bicubic 100x100 T-mesh on [0.25, 28.75] x [-0.125, 31.125] at 512x512: 103
// float ulps, against 5.6 with the local parameter from double). Grid and span grid take nu + nv
// searches against nu * nv evaluations; an explicit list one per sample (in the upload).
//
// Samplings: grid, span grid (cells between knot lines), explicit. f32 everywhere, f64 where the
// device has cl_khr_fp64 (refused otherwise). Degree <= kMaxDegree (15): the kernel keeps only
// four Bernstein rows of kMaxOrder reals per work-item. T-spline scenes only
// (Capabilities::tspline_only). The program is built once per precision (first prepare());
// DeviceInfo::details counts "program_builds" and gives "elements", "extraction_reals",
// "extraction_s" (the host's influence index and extraction in the last prepare()) and
// "decompose_s" (the last decomposition kernel's seconds).
//
// Options (StrategyOptions.extra): "device" = N, the N-th OpenCL device over all platforms.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyDescriptor cl_tspline_bezier_descriptor();
StrategyEntry cl_tspline_bezier_entry();

}  // namespace nurbs
