#version 450
#extension GL_GOOGLE_include_directive : require
// Direct trimming's compute pass (Schollmeyer & Fröhlich 2009), shared by the Vulkan strategies
// (strategies/vulkan/vk_trim_classify.h): one invocation per sample of one trimmed surface,
// classified by td_classify of the single-source strategies/trim_direct/trim_direct.h.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer TdReals { float td_reals[]; };
layout(std430, set = 0, binding = 1) readonly buffer TdInts { int td_ints[]; };
// Per trimmed surface: its grid's u then v parameters in the trim's local frame.
layout(std430, set = 0, binding = 2) readonly buffer Coords { float coords[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Inside { uint inside[]; };
layout(std430, set = 0, binding = 4) writeonly buffer Reads { int reads[]; };
layout(push_constant) uniform Launch {
  int base;  // the surface's tables in td_ints
  int u_offset, nu, v_offset, nv;
  int out_base;  // its first sample in `inside` / `reads`
  float epsilon;
  int iterations;
  int paired;  // 1: sample k is (u[k], v[k]) and nv = 1 (explicit lists, a tessellator's own)
} launch;

#include "../trim_direct/trim_direct.h"

void main() {
  const int k = int(gl_GlobalInvocationID.x);
  if (k >= launch.nu * launch.nv) return;
  const int a = launch.paired != 0 ? k : k / launch.nv;
  const int b = launch.paired != 0 ? k : k % launch.nv;
  const int packed = td_classify(launch.base, coords[launch.u_offset + a],
                                 coords[launch.v_offset + b], launch.epsilon, launch.iterations);
  inside[launch.out_base + k] = uint(packed & 1);
  reads[launch.out_base + k] = packed / 2;
}
