// cpu-tensor: the fast CPU grid evaluator (issue #6). Grid and span-grid samples are tensor
// products of a u-list and a v-list (reference/sampling.h), so the basis functions are computed
// once per u sample and once per v sample (Macri 1999, 004: "pre-evaluate the basis functions at
// the tessellation steps"); each output row contracts the (p+1) control-point rows of its u span
// into the homogeneous control points of one iso-curve, then every sample of the row is the
// (q+1)-term contraction of that curve, vectorised across samples, rows spread over the cores.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry cpu_tensor_entry();

}  // namespace nurbs
