#version 450
#extension GL_GOOGLE_include_directive : require
// Evaluation stage of the nonuniform mapping (003 §4's third: tessellator, then a geometry stage
// for the sampler's adaptivity). point_mode: the control stage (ksquad.tesc, nonuniform branch)
// gives the KSQuad a regular level_u x level_v lattice; each lattice vertex (i, j) with i < level_u
// and j < level_v starts a KSDie {(x_k, y_l), δx = 1 / level_u, δy = 1 / level_v} (003 §3.1), whose
// four corners are evaluated here, as 003 §4's domain shader does, and passed to the geometry
// stage (ksquad_nonuniform.geom). Other points (the far edges; the centre the tessellator adds
// where a level of 1 is raised to 2) start no KSDie.
layout(quads, equal_spacing, ccw, point_mode) in;
layout(constant_id = 0) const int kRaster = 0;
layout(constant_id = 1) const int kDegreeU = 0;
layout(constant_id = 2) const int kDegreeV = 0;
#define DEGREE_U(s) (kDegreeU > 0 ? kDegreeU : surfaces[s])
#define DEGREE_V(s) (kDegreeV > 0 ? kDegreeV : surfaces[(s) + 1])
#include "ksquad_tables.glsl"
#include "../stair_basis/stair_basis.h"
#include "ksquad_point.glsl"
layout(location = 0) patch in vec2 piece_corners[4];  // unused here (adaptive pieces)
layout(location = 4) patch in int patch_row;
layout(location = 0) flat out ivec4 die;  // patch row, i, j, 1 when this point starts a KSDie
layout(location = 1) flat out ivec2 die_levels;
layout(location = 2) out vec3 die_corners[4];  // S at (i, j), (i+1, j), (i, j+1), (i+1, j+1)

void main() {
  const int row = patch_row * PATCH_INTS;
  const int s = patches[row] * SURFACE_INTS;
  const int span_u = patches[row + 1], span_v = patches[row + 2];
  const int cu = patches[row + 3], cv = patches[row + 4];
  const int pu = DEGREE_U(s), pv = DEGREE_V(s);
  const int level_u = int(gl_TessLevelOuter[1]), level_v = int(gl_TessLevelOuter[0]);
  const vec2 t = gl_TessCoord.xy * vec2(level_u, level_v);
  const ivec2 ij = ivec2(round(t));
  const bool starts = all(lessThan(abs(t - vec2(ij)), vec2(1e-3))) && ij.x < level_u &&
                      ij.y < level_v;
  die = ivec4(patch_row, ij, starts ? 1 : 0);
  die_levels = ivec2(level_u, level_v);
  gl_Position = vec4(0.0);
  for (int k = 0; k < 4; ++k) die_corners[k] = vec3(0.0);
  if (!starts) return;
  for (int k = 0; k < 4; ++k) {
    // the KSDie's corner parameter (i + di) / level: exact at the KSQuad's knots
    const float u = span_parameter(cu, pu, 0.0, 1.0, float(ij.x + (k & 1)) / float(level_u));
    const float v = span_parameter(cv, pv, 0.0, 1.0, float(ij.y + (k >> 1)) / float(level_v));
    die_corners[k] = ksquad_point(s, span_u, span_v, cu, cv, u, v);
  }
}
