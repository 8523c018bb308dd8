// cpu-coxdeboor: the papers' CPU baseline. Per sample: span search (A2.1), the basis by the
// triangular Cox-de Boor scheme (A2.2), the (p+1)(q+1) homogeneous sum and the divide (A4.3).
// Single-threaded and unvectorised on purpose: it is the "CPU" of the papers' speedup charts
// (000 §5, 002 §5); the fast CPU evaluator a product would use is cpu-tensor. It trims: classify()
// runs the reference's trim classifier (reference/trim_classify.h) in double on its samples.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry cpu_coxdeboor_entry();

}  // namespace nurbs
