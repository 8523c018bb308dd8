// vk-ksquad: RPNS 2014 (003 §2-4) KSQuads evaluated in Vulkan tessellation stages. One patch per
// KSQuad (a non-empty span pair holding samples; strategies/ksquad/ksquad_table.h); the control
// stage sets its tessellation levels, the evaluation stage evaluates the KSQuad at the
// tessellator's vertex with the stair basis (strategies/cl_stair/stair_basis.h) and writes the
// position to a storage buffer. Info-KSQuad table, surface table, per-span stair constants,
// control points and parameters live in storage buffers (003 Fig 8's two-level indirection), so
// the degree is not bounded by maxTessellationPatchSize. f32 positions; grid and span grid.
//
// Options (StrategyOptions.extra): "device" = N, the N-th Vulkan physical device.
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry vk_ksquad_entry();

}  // namespace nurbs
