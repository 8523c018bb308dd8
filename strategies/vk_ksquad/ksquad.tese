#version 450
#extension GL_GOOGLE_include_directive : require
// Evaluation stage (003 §4's domain shader): evaluates the KSQuad at the tessellator's vertex
// with the stair basis and writes the result to a storage buffer.
//  * uniform (vk-mode=uniform; not 003 §4's "uniform" mapping, which is our adaptive mode: eq.
//    3's levels): the requested lattice, the levels are the segment counts of the patch's runs
//    (ksquad.tesc), and the slot of a vertex is its lattice index (a, b), so a vertex evaluated
//    twice writes the same value to the same place. The parameter:
//     - span grid: the tessellator chooses it: span_parameter() of gl_TessCoord over the patch's
//       share of its KSQuad's spans (the whole span unless the run was cut), written with the
//       position and returned as the sample (vk_ksquad.cpp read_back);
//     - grid (our choice; 003 draws only the tessellator's own lattices): a regular grid of the
//       domain is not equally spaced from each knot, so no tessellator lattice of a KSQuad holds
//       its samples. gl_TessCoord picks the lattice vertex (a, b) of the patch's runs and the
//       parameter is the requested one (the float rounding of sample_parameters), so results
//       are measured at exactly the requested (u, v).
//  * adaptive (003 §4's second mapping, the one the paper says "obtains a uniform result"):
//    (u, v) = span_parameter() of gl_TessCoord over the KSQuad, captured with (u, v) in
//    the patch's region of slots: one per vertex of each outer edge, then the inner lattice; a
//    slot again depends only on the vertex.
//  * raster (specialization constant 0 = 1; the render() path, 003 §4's pipeline end to end): in
//    every mode the parameter is span_parameter() of gl_TessCoord, so every patch spans its share
//    of its KSQuad up to the knot lines and neighbours share their boundary vertices (a grid's
//    samples stop short of the knots: rendering them left a gap along every knot line); the
//    position is projected to gl_Position and rasterized; nothing is stored.
layout(quads, equal_spacing, ccw) in;
layout(constant_id = 0) const int kRaster = 0;
// One pipeline per degree pair of the scene (patches are drawn grouped by it): the degrees as
// specialization constants give the basis loops constant bounds (a runtime degree made llvmpipe
// several times slower, as glsl-deboor found for its fragment passes). 0: read the table.
layout(constant_id = 1) const int kDegreeU = 0;
layout(constant_id = 2) const int kDegreeV = 0;
#define DEGREE_U(s) (kDegreeU > 0 ? kDegreeU : surfaces[s])
#define DEGREE_V(s) (kDegreeV > 0 ? kDegreeV : surfaces[(s) + 1])
#include "ksquad_tables.glsl"
// The single-source stair basis (stair_basis, stair_derivative) on the `consts` buffer.
#include "../stair_basis/stair_basis.h"
#include "ksquad_point.glsl"
// From the control stage (ksquad.tesc): the patch's row and, adaptive, its piece of the KSQuad.
layout(location = 0) patch in vec2 piece_corners[4];
layout(location = 4) patch in int patch_row;
#undef PATCH
#define PATCH patch_row
// Raster: the fragment stage's trim test (ksquad.frag) classifies the interpolated (u, v).
layout(location = 0) out vec2 trim_uv;
layout(location = 1) flat out int trim_surface;


int adaptive_slot() {
  const vec2 t = gl_TessCoord.xy;
  const int edge = mode.max_level + 1;
  if (t.x == 0.0) return int(round(t.y * gl_TessLevelOuter[0]));
  if (t.y == 0.0) return edge + int(round(t.x * gl_TessLevelOuter[1]));
  if (t.x == 1.0) return 2 * edge + int(round(t.y * gl_TessLevelOuter[2]));
  if (t.y == 1.0) return 3 * edge + int(round(t.x * gl_TessLevelOuter[3]));
  const int i = int(round(t.x * gl_TessLevelInner[0])), j = int(round(t.y * gl_TessLevelInner[1]));
  return 4 * edge + (i - 1) * (mode.max_level - 1) + (j - 1);
}

void main() {
  const int row = PATCH * PATCH_INTS;
  const int s = patches[row] * SURFACE_INTS;
  const int span_u = patches[row + 1], span_v = patches[row + 2];
  const int cu = patches[row + 3], cv = patches[row + 4];
  const int pu = DEGREE_U(s), pv = DEGREE_V(s);
  int a = 0, b = 0;
  if (mode.adaptive == 0) {
    const int u_begin = patches[row + 5], u_count = patches[row + 6];
    const int v_begin = patches[row + 7], v_count = patches[row + 8];
    const int level_u = patches[row + 9], level_v = patches[row + 10];
    a = lattice_index(gl_TessCoord.x, level_u, u_begin, u_count);
    b = lattice_index(gl_TessCoord.y, level_v, v_begin, v_count);
  }
  float u, v;
  if (mode.adaptive != 0) {
    // the piece's bilinear map: exact on its edges (t = 0 or 1), which neighbours share
    const vec2 t = gl_TessCoord.xy;
    const vec2 f = (1.0 - t.y) * ((1.0 - t.x) * piece_corners[0] + t.x * piece_corners[1]) +
                   t.y * ((1.0 - t.x) * piece_corners[2] + t.x * piece_corners[3]);
    u = span_parameter(cu, pu, 0.0, 1.0, f.x);
    v = span_parameter(cv, pv, 0.0, 1.0, f.y);
  } else if (kRaster != 0 || mode.span_grid != 0) {
    u = span_parameter(cu, pu, intBitsToFloat(patches[row + 20]), intBitsToFloat(patches[row + 21]),
                       gl_TessCoord.x);
    v = span_parameter(cv, pv, intBitsToFloat(patches[row + 22]), intBitsToFloat(patches[row + 23]),
                       gl_TessCoord.y);
  } else {
    u = params[surfaces[s + 5] + a];
    v = params[surfaces[s + 6] + b];
  }
  const vec3 position = ksquad_point(s, span_u, span_v, cu, cv, u, v);
  if (kRaster == 0 && mode.normals != 0) {
    // SB_KNOT(c, p) = x_{i+1}: the span's end knot belongs to the next span (row + 16..19).
    // Adaptive: one normal per capture slot, in the slot's place.
    const bool u_end = u == SB_KNOT(cu, pu), v_end = v == SB_KNOT(cv, pv);
    write_normal(mode.adaptive != 0 ? PATCH * mode.region + adaptive_slot()
                                    : surfaces[s + 8] + a * surfaces[s + 7] + b,
                 s,
                 u_end ? patches[row + 16] : span_u, v_end ? patches[row + 17] : span_v,
                 u_end ? patches[row + 18] : cu, v_end ? patches[row + 19] : cv, u, v);
  }
  if (kRaster != 0) {
    gl_Position = mode.view_projection * vec4(position, 1.0);
    trim_uv = vec2(u, v);
    trim_surface = patches[row];
  } else if (mode.adaptive == 0) {
    const int slot = surfaces[s + 8] + a * surfaces[s + 7] + b;
    positions[3 * slot] = position.x;
    positions[3 * slot + 1] = position.y;
    positions[3 * slot + 2] = position.z;
    if (mode.span_grid != 0) {
      sample_params[2 * slot] = u;
      sample_params[2 * slot + 1] = v;
    }
  } else {
    const int o = SLOT_FLOATS * (PATCH * mode.region + adaptive_slot());
    positions[o] = u;
    positions[o + 1] = v;
    positions[o + 2] = position.x;
    positions[o + 3] = position.y;
    positions[o + 4] = position.z;
  }
}
