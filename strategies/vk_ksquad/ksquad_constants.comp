#version 450
#extension GL_GOOGLE_include_directive : require
// The per-span stair constants (003 §3.2: "computed only once" per KSQuad direction) on the device
// (vk-constants=device, the default): one invocation per (surface, direction, non-empty span),
// stair_constants of the single-source header, compiled here as GLSL, from the knot vectors as
// floats -- 003 §1's "whole NURBS equation in the GPU without any precomputation on the CPU". The
// pass runs once per prepare (the constants depend on the knots alone, so a deforming frame,
// which moves control points, never reruns it). Its own descriptor set (vk_ksquad.cpp
// constants_set_): the knots, the jobs, and the constants buffer the draws read.
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Knots { float sb_knots[]; };
// Per job: the knot vector's offset in `knots`, the degree, the span, the constants' offset.
layout(std430, set = 0, binding = 1) readonly buffer Jobs { int jobs[]; };
layout(std430, set = 0, binding = 2) buffer Constants { float consts[]; };
layout(push_constant) uniform Count { int jobs; } count;
#define SB_GLSL_CONSTANTS 1
#include "../stair_basis/stair_basis.h"

void main() {
  const int k = int(gl_GlobalInvocationID.x);
  if (k >= count.jobs) return;
  stair_constants(jobs[4 * k + 2], jobs[4 * k + 1], jobs[4 * k], jobs[4 * k + 3]);
}
