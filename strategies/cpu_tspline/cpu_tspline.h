// cpu-tspline: 001's T-spline evaluation on the CPU, the method Krishnamurthy and Yasui describe
// and could not run on the GPU. prepare() is their CPU pre-processing: the influence index
// (reference/tspline.h TSplineInfluence, 001 Fig 7: per region the control points whose blending
// function is non-zero there). Per sample: the region by two binary searches, then each active
// point's blending function N[u_k](u) N[v_k](v) directly on its local knot vectors (001 eq. 4-5),
// the homogeneous sum and the rational divide. The same code as the reference (evaluate_tspline)
// at float or double, single-threaded: the T-spline counterpart of cpu-coxdeboor, the CPU of the
// speedup charts. T-splines only; NURBS scenes are refused.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry cpu_tspline_entry();

}  // namespace nurbs
