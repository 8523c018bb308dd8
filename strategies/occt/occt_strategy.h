// occt: OpenCASCADE Geom_BSplineSurface as a peer (never the reference). Per sample D0 (points)
// or D1 (points and first derivatives, normal = Su x Sv), any sampling; OCCT computes in double,
// f32 requests get its results rounded. Where Su x Sv is rounding noise (collapsed edges) the
// normal is the project's limit rule (nurbs_math.h). Built when the OCCT packages are installed.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry occt_entry();

}  // namespace nurbs
