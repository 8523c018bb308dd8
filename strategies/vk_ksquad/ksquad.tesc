#version 450
#extension GL_GOOGLE_include_directive : require
// Control stage (003 §4's hull shader): one patch per KSQuad (or per piece of one, where a run
// needs more than maxTessellationGenerationLevel segments), levels from its Info-KSQuad row.
// Vulkan quads: outer[0] is the edge u = 0 and outer[2] the edge u = 1 (both run along v),
// outer[1] the edge v = 0 and outer[3] the edge v = 1 (along u); inner[0] along u, inner[1]
// along v. Each edge level is the segment count of that edge's own run of samples, so two
// patches sharing an edge choose the same level.
layout(vertices = 1) out;
#include "ksquad_tables.glsl"

void main() {
  const int row = gl_PrimitiveID * PATCH_INTS;
  const float level_u = float(patches[row + 9]), level_v = float(patches[row + 10]);
  gl_TessLevelOuter[0] = level_v;
  gl_TessLevelOuter[1] = level_u;
  gl_TessLevelOuter[2] = level_v;
  gl_TessLevelOuter[3] = level_u;
  gl_TessLevelInner[0] = level_u;
  gl_TessLevelInner[1] = level_v;
}
