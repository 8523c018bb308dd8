// vk-bezier: RPNS's baseline (003 §2) tessellated on the GPU. The CPU decomposes every NURBS
// surface into rational Bézier patches (The NURBS Book A5.6/A5.7, reference/bezier_decomposition.h,
// in double) and uploads their homogeneous control points as floats; Vulkan tessellates one patch
// per Bézier patch through vk-ksquad's pipeline (its tables, vertex and control stages, uniform
// mapping, run cutting and draws; strategies/vk_ksquad/) with its own evaluation stage
// (bezier.tese: Bernstein basis on the patch-local parameter, homogeneous sum, divide), the results
// written to a storage buffer. update_control_points() decomposes again and uploads every Bézier
// point, the baseline's per-frame cost; vk-ksquad re-sends only the NURBS points, and cpu-bezier
// decomposes and evaluates on the CPU -- `run --deforming N` compares the three.
//
// f32 positions and normals, grid and span grid, degrees up to 15; no trims, no T-splines.
// Options (StrategyOptions.extra): "device" = N, the N-th Vulkan physical device;
// vk-vertices-per-draw = N (as vk-ksquad's, strategies/vk_ksquad/ksquad_settings.h).
#pragma once

#include <string_view>

#include "strategies/registry.h"

namespace nurbs {

inline constexpr std::string_view kVkBezierSource =
    "RPNS 2014 (003 §2): the Bézier-decomposition baseline, tessellated on the GPU";

StrategyDescriptor vk_bezier_descriptor();
StrategyEntry vk_bezier_entry();

}  // namespace nurbs
