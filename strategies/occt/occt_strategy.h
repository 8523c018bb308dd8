// occt: OpenCASCADE Geom_BSplineSurface as a peer (never the reference). Per sample D0 (points)
// or D1 (points and first derivatives, normal = Su x Sv), any sampling; OCCT computes in double,
// f32 requests get its results rounded. Where Su x Sv is rounding noise (collapsed edges) the
// normal is the project's limit rule (nurbs_math.h). Built when the OCCT packages are installed.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry occt_entry();
// The same through GeomAdaptor_Surface, whose per-span cache OCCT users rely on for grids.
StrategyEntry occt_cached_entry();

}  // namespace nurbs
