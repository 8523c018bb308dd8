// vk-ksquad: RPNS 2014 (003 §2-4) KSQuads evaluated in Vulkan tessellation stages. One patch per
// KSQuad (a non-empty span pair holding samples; strategies/ksquad/ksquad_table.h); the control
// stage sets its tessellation levels, the evaluation stage evaluates the KSQuad at the
// tessellator's vertex with the stair basis (strategies/stair_basis/stair_basis.h) and writes the
// position to a storage buffer. Info-KSQuad table, surface table, per-span stair constants,
// control points and parameters live in storage buffers (003 Fig 8's two-level indirection), so
// the degree is not bounded by maxTessellationPatchSize. f32 positions and normals; grid and span
// grid. Files: vk_ksquad_class.h + vk_ksquad.cpp (the strategy class and what every mapping
// shares: tables, draws, capture, render), uniform_mapping.*, adaptive_mapping.*, gs_mapping.cpp
// and nonuniform_mapping.* (each mapping's own members and host pieces; nonuniform: the friend
// surfaces and the geometry stage's KSDie records), ksquad_pipeline.* (pipelines, render target),
// ksquad_settings.* (options, camera), patches.h (cutting runs), ksquad_layout.h (table layouts).
//
// Trims (Capabilities::trims, uniform mode): classify() is direct trimming (Schollmeyer &
// Fröhlich 2009) in a compute pass over the requested samples (vulkan::TrimClassifier, the
// single-source strategies/trim_direct/trim_direct.h as GLSL, float); adaptive mode refuses
// trimmed scenes. The cost counter (buffer elements read per sample) is in DeviceInfo::details.
//
// Options (StrategyOptions.extra): vk-mode, vk-eye, vk-center, vk-fov, vk-viewport, vk-mu,
// vk-max-level, vk-pieces, vk-corners, vk-vertices-per-draw (ksquad_settings.h);
// "device" = N, the N-th Vulkan physical device;
// "trim-epsilon" = E (bisection width, a fraction of the domain diagonal; default 1e-9) and
// "trim-iterations" = N (1..64, default 40).
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyDescriptor vk_ksquad_descriptor();
StrategyEntry vk_ksquad_entry();

}  // namespace nurbs
