// vk-ksquad's strategy object, for tests that look past the Strategy contract (pipeline
// statistics). Vulkan builds only; the harness uses vk_ksquad_entry().
#pragma once

#include <cstdint>
#include <memory>

#include "strategies/strategy.h"

namespace nurbs {

// The last evaluate(): what the pipeline statistics counted and what the chosen levels imply.
struct KsquadStatistics {
  std::uint64_t patches_drawn = 0;           // rows of the Info-KSQuad table
  std::uint64_t control_patches = 0;         // pipeline statistics: TCS patches
  std::uint64_t evaluation_invocations = 0;  // pipeline statistics: TES invocations (KSDice)
  std::uint64_t implied_vertices = 0;        // sum over patches of quad_domain_vertices(levels)
  int max_level = 0;                         // largest level set
  int level_cap = 0;                         // maxTessellationGenerationLevel
};

std::unique_ptr<Strategy> make_vk_ksquad(const StrategyOptions& options);
// `strategy` must come from make_vk_ksquad; throws std::invalid_argument otherwise.
KsquadStatistics ksquad_statistics(const Strategy& strategy);

}  // namespace nurbs
