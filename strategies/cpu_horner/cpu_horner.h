// cpu-horner: the CPU method of Macri 1999 (004). Per knot span the power-basis coefficients of
// every non-zero basis function, computed once per knot vector (prepare); each sample's basis
// functions and their derivatives by Horner's rule from those coefficients; the (p+1)(q+1) sum
// with the four homogeneous coordinates processed together; normals from Su x Sv.
// StrategyOptions.extra["horner-origin"] = "span" (default: t = u - u_s) or "zero" (Macri's
// expansion in u itself, which loses digits as the degree grows; see power_basis.h).
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry cpu_horner_entry();

}  // namespace nurbs
