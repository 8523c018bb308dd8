// Tests: the GLSL build of the single-source stair basis (stair_basis.comp) through the shared
// Vulkan plumbing. Vulkan builds only.
#pragma once

#include <vector>

#include "strategies/stair_basis/stair.h"

namespace nurbs::vulkan {

struct StairJob {
  int constants = 0;  // offset of the span's StairConstants<float> in `constants`
  int degree = 1;
  bool derivative = false;
  float u = 0;
};

// kStairMaxDegree + 1 values per job (the first degree + 1 set): the basis or its derivative at
// job.u from the constants the C++ build computed, on Vulkan device `device_index`.
std::vector<float> stair_basis_on_vulkan(const std::vector<float>& constants,
                                         const std::vector<StairJob>& jobs, int device_index);

}  // namespace nurbs::vulkan
