// cpu-bezier: the baseline RPNS beats (003 §2, Fig. 3(a)). prepare() -- timed as `upload` --
// decomposes every surface into rational Bézier patches by knot insertion to full multiplicity
// (The NURBS Book A5.6/A5.7, reference/bezier_decomposition.h); evaluate() locates each sample's
// patch by the span search the other strategies use (A2.1) and evaluates the rational Bézier patch
// there. update_control_points() redoes the whole decomposition: moving one NURBS control point
// changes every Bézier point built from it, which is the cost RPNS's KSQuads avoid (003 §2).
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry cpu_bezier_entry();

}  // namespace nurbs
