// vk-compute (issue 29): cpu-tensor's tensor-product separation (strategies/cpu_tensor/) as
// Vulkan compute dispatches on the shared plumbing (strategies/vulkan/). Two passes in one
// submission, every surface of the scene in each:
//  1. basis pass (basis.glsl): span, basis functions and first derivatives of every distinct
//     parameter list (surfaces sampled alike share one) computed on the device from the knot
//     vectors by the single-source tensor_basis.h (the same header compiled as C++);
//  2. evaluation pass (eval.glsl): one work-group per tile of a surface table -- the u
//     contraction of the homogeneous net into the tile rows' iso-curves in shared memory, then the
//     v contraction and the divide per sample; explicit lists the direct (p+1)(q+1) sum.
// Work-group size and shared-memory tile come from maxComputeWorkGroupInvocations /
// maxComputeWorkGroupSize and maxComputeSharedMemorySize (specialization constants).
//
// f32, and f64 where the device has shaderFloat64 (refused with the reason where it does not);
// degrees 1-15; grid, span grid, explicit lists; normals (the reference's limit-normal fallback,
// its last stage on the host for the rare samples the device leaves unresolved); trims by direct
// trimming in the next dispatch (vulkan::TrimClassifier, classify()); update_control_points()
// re-sends only the nets; device timestamps around both passes (device_times()).
// Options (StrategyOptions.extra): "device" = N, the N-th Vulkan physical device;
// "trim-epsilon", "trim-iterations" as vk-ksquad's.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "strategies/registry.h"

namespace nurbs {

inline constexpr std::string_view kVkComputeSource =
    "issue 29: cpu-tensor's tensor-product separation (004, Macri 1999) as Vulkan compute "
    "dispatches, basis on the device, every surface in one dispatch";

StrategyDescriptor vk_compute_descriptor();
StrategyEntry vk_compute_entry();

namespace vk_compute {

// Tests: the GLSL build of tensor_basis.h (the basis pass) on Vulkan device `device_index`, every
// job in one dispatch: per job, per parameter its span and TB_STRIDE values (basis, then
// derivatives). f64: the double shader (RefusedError where the device has no shaderFloat64).
struct BasisJob {
  std::vector<double> knots;
  int degree = 1;
  std::vector<double> params;
};
struct BasisRun {
  std::vector<int> spans;
  std::vector<double> values;
};
std::vector<BasisRun> basis_on_vulkan(const std::vector<BasisJob>& jobs, bool f64,
                                      int device_index);

}  // namespace vk_compute
}  // namespace nurbs
