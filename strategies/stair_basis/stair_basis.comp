#version 450
#extension GL_GOOGLE_include_directive : require
// Tests only: the GLSL build of the single-source stair basis (stair_basis.h), one invocation per
// job (strategies/stair_basis/vk_stair_basis.h), so the test compares it with the C++ and OpenCL
// builds on the same inputs.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Constants { float consts[]; };
// Per job: offset of its constants in `consts`, degree, 1 for the derivative.
layout(std430, set = 0, binding = 1) readonly buffer Jobs { int jobs[]; };
layout(std430, set = 0, binding = 2) readonly buffer Params { float params[]; };
layout(std430, set = 0, binding = 3) writeonly buffer Values { float values[]; };
layout(push_constant) uniform Launch { int count; } launch;

#include "stair_basis.h"

void main() {
  const int k = int(gl_GlobalInvocationID.x);
  if (k >= launch.count) return;
  const int c = jobs[3 * k], degree = jobs[3 * k + 1];
  float b[SB_MAX_ORDER];
  if (jobs[3 * k + 2] != 0)
    stair_derivative(c, degree, params[k], b);
  else
    stair_basis(c, degree, params[k], b, degree);
  for (int j = 0; j <= degree; ++j) values[SB_MAX_ORDER * k + j] = b[j];
}
