// VkKsquad's GS mapping (003 §4's first, vk-mode=gs): no tessellator; the geometry stage
// evaluates or emits each KSQuad's span-grid lattice (ksquad.geom), T <= 8 by its output limit.
#include <fmt/format.h>

#include "strategies/vk_ksquad/vk_ksquad_class.h"

namespace nurbs::vk_ksquad {

namespace {
// ksquad.geom: max_vertices, the strips of span grid T = kGsMaxSteps (T strips of 2 (T + 1))
constexpr std::uint32_t kGsMaxVertices = 144;
constexpr int kGsMaxSteps = 8;
static_assert(kGsMaxSteps * 2 * (kGsMaxSteps + 1) == kGsMaxVertices);
}  // namespace

void VkKsquad::check_gs_limits() const {
  const VkPhysicalDeviceLimits& limits = device_.limits();
  if (limits.maxGeometryOutputVertices < kGsMaxVertices ||
      limits.maxGeometryTotalOutputComponents < kGsMaxVertices * 7)
    throw vulkan::MissingFeature(
        fmt::format("vk-mode=gs needs {} geometry output vertices of 7 components (ksquad.geom)",
                    kGsMaxVertices));
}

void VkKsquad::refuse_gs(const EvalRequest& request) const {
  if (request.sampling.mode != SamplingMode::span_grid || request.sampling.span_steps > kGsMaxSteps)
    throw RefusedError(fmt::format(
        "vk-ksquad vk-mode=gs: span grids of at most {} steps only (a KSQuad's KSDice must fit "
        "one geometry-shader invocation's output, 003 §4)",
        kGsMaxSteps));
}

}  // namespace nurbs::vk_ksquad
