// vk-ksquad's uniform mapping (the harness's requested lattice; 003 §4's "uniform" version is our
// adaptive mapping, eq. 3's levels: here the levels are the request's run
// lengths): its host pieces. See ksquad.tese for which parameter the evaluation stage takes.
#pragma once

#include <vector>

#include "reference/sampling.h"
#include "strategies/ksquad/ksquad_table.h"

namespace nurbs::vk_ksquad {

// The surface table (ksquad_tables.glsl SURFACE_INTS per surface) and the requested parameters
// as floats, for the uniform mapping's samples; `total`: samples over all surfaces (the output's
// length). The record's first point counts the NURBS control points (vk-ksquad's net).
struct SurfaceTable {
  std::vector<int> surfaces;
  std::vector<float> params;
  std::size_t total = 0;
};
SurfaceTable surface_table(const Scene& scene, const std::vector<SurfaceSamples>& samples);

// A grid's KSQuads: every pair of non-empty spans, those without samples included (no samples
// captured; drawn, they cover their span: see with_empty_spans).
std::vector<ksquad::KSQuad> grid_ksquads(const Scene& scene,
                                         const std::vector<SurfaceSamples>& samples);

// The span grid's samples as the device evaluated them (`uv`: u, v per sample of `requested`'s
// layout).
SurfaceSamples chosen_samples(const SurfaceSamples& requested, const float* uv);

}  // namespace nurbs::vk_ksquad
