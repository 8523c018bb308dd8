// sisl: SINTEF SISL as a peer (docs/design.md §Strategies). Grids and span grids through SISL's
// grid evaluator s1506 (B-splines pre-evaluated per grid line, s1504, then multiplied out, s1505);
// explicit lists per sample through s1424. SISL computes in double (f32 requests: rounded results).
// Where SISL's Su x Sv is rounding
// noise (collapsed edges) the normal is the project's limit rule (nurbs_math.h), as SISL itself
// returns a zero normal there. Built when libsisl-dev is installed, unavailable otherwise.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry sisl_entry();

}  // namespace nurbs
