// cpu-horner: the CPU method of Macri 1999 (004). Per knot span the power-basis coefficients of
// every non-zero basis function, computed once per knot vector (prepare); the basis functions and
// their derivatives at a grid's parameters by Horner's rule from those coefficients, once per
// tessellation (prepare), looked up per frame; the (p+1)(q+1) sum with the four homogeneous
// coordinates processed together; normals from Su x Sv. A deforming frame swaps the net only.
// StrategyOptions.extra["horner-origin"] = "span" (default: t = u - u_s) or "zero" (Macri's
// expansion in u itself, which loses digits as the degree grows; see power_basis.h).
// StrategyOptions.extra["horner-simd"] = "auto" (default: the compiler's vectorisation of a loop
// over xyzw) or "explicit" (004's TessellateSurfaceSSE: SSE intrinsics; x86 builds only).
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry cpu_horner_entry();

}  // namespace nurbs
