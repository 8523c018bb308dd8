#version 450
#extension GL_GOOGLE_include_directive : require
// The KSQuad corners S(x_k, y_l) of adaptive mode on the device (vk-corners=device), one
// invocation per corner, before the draws that project them (003 §1: the whole NURBS equation
// evaluated on the GPU, nothing precomputed on the CPU; §4's hull shader reads them). Each corner
// is evaluated once, with the span A2.1 assigns its knots to, so every KSQuad meeting there reads
// the same value -- evaluating it in each KSQuad's control stage with its own span would give
// neighbours different floats, different levels and cracks. mode.patch_base: the corner count.
layout(local_size_x = 64) in;
#define KSQUAD_CORNERS_ACCESS writeonly
#include "ksquad_tables.glsl"
#define DEGREE_U(s) surfaces[s]
#define DEGREE_V(s) surfaces[(s) + 1]
// The single-source stair basis (stair_basis, stair_derivative) on the `consts` buffer.
#include "../stair_basis/stair_basis.h"
#include "ksquad_point.glsl"

void main() {
  const int k = int(gl_GlobalInvocationID.x);
  if (k >= mode.patch_base) return;
  const int j = CORNER_INTS * k;
  const int s = corner_jobs[j], cu = corner_jobs[j + 3], cv = corner_jobs[j + 4];
  const int pu = DEGREE_U(s), pv = DEGREE_V(s);
  // SB_KNOT(c, p - 1) = x_i, SB_KNOT(c, p) = x_i+1 (StairConstants::knots)
  const float u = corner_jobs[j + 5] != 0 ? SB_KNOT(cu, pu) : SB_KNOT(cu, pu - 1);
  const float v = corner_jobs[j + 6] != 0 ? SB_KNOT(cv, pv) : SB_KNOT(cv, pv - 1);
  corners[k] = vec4(ksquad_point(s, corner_jobs[j + 1], corner_jobs[j + 2], cu, cv, u, v), 1.0);
}
