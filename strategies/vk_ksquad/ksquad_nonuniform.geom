#version 450
#extension GL_GOOGLE_include_directive : require
// Geometry stage of the nonuniform mapping (003 §3.1's sampler tests, §4's third mapping): one
// invocation per point of the tessellator (ksquad_nonuniform.tese); a point that starts a KSDie
// brings its four corners. In this order:
//  1. Exact Visible Set culling (003 §4) on the four corners: view frustum -- culled when all four
//     lie outside one clip plane (a KSDie bulging back into view past its corners is lost: the
//     paper tests no more than its corners either); then back face -- with every corner in front
//     of the eye, culled when the projected quad (0,0) (1,0) (1,1) (0,1) winds as a surface whose
//     Su x Sv points away from the eye does: signed area > 0 in eq. 3's pixel frame (its y axis
//     is the flipped clip y, so a front face winds clockwise there). Culled KSDice are recorded,
//     not subdivided, not emitted.
//  2. Subdivision. 003 says the geometry stage "subdivides each KSDie further" but not how within
//     its output limit; we chose a fixed maximum depth NU_DEPTH = 2 per KSDie (up to 4 x 4
//     sub-KSDice, 4 strips of 10 vertices = 40 <= maxGeometryOutputVertices, 40 x 7 components),
//     uniform inside the KSDie, the depth the larger of:
//     - eq. 4, the linear-approximation test: at depth d the KSDie is 2^d x 2^d cells; a cell
//       passes when at its centre and at its four edge midpoints |p(S(u, v)) - p(S'(u, v))| < ε,
//       S' the point the unsubdivided cell renders at (u, v): the cell is drawn as the two
//       triangles of step 3's strip, (0,0) (0,1) (1,0) and (0,1) (1,0) (1,1), so an edge midpoint
//       renders at the mean of its edge's two corners and the centre, on the shared diagonal
//       (0,1)-(1,0), at the mean of those two corners -- not at the bilinear mean of all four,
//       which no drawn triangle passes through (the rasterizer interpolates the world-space
//       triangle, so p(S') is the projection of that barycentric point); the depth is the smallest
//       d whose cells all pass (003 takes the max over the whole cell; we sample it at those five
//       points), else NU_DEPTH;
//     - eq. 5, the boundary-region test, on the sides the f tag marks: the smallest d at which
//       every one of the 2^d pieces of each marked side projects shorter than η, else NU_DEPTH.
//     f (003 §3.1's 4-bit tag): bit e set when side e of the KSDie (0 u = lo, 1 v = lo, 2 u = hi,
//     3 v = hi) lies on the surface's domain side e and that side is shared with a surface that
//     is not its friend (surfaces[s + 9], found once on the host: nonuniform_mapping.cpp).
//  3. Emission: two triangles per (sub-)KSDie, strips of its lattice; every emitted vertex's (u,
//     v), position and normal stored in its slot (ksquad_nonuniform.glsl), and the KSDie's record.
//     The lattice is evaluated on the KSDie's own spans (the stair basis holds on the closed span);
//     a normal on the span's end knot uses the next span, as A2.1 and the reference do.
layout(points) in;
layout(triangle_strip, max_vertices = 40) out;
layout(constant_id = 0) const int kRaster = 0;
layout(constant_id = 1) const int kDegreeU = 0;
layout(constant_id = 2) const int kDegreeV = 0;
#define DEGREE_U(s) (kDegreeU > 0 ? kDegreeU : surfaces[s])
#define DEGREE_V(s) (kDegreeV > 0 ? kDegreeV : surfaces[(s) + 1])
#include "ksquad_tables.glsl"
#include "../stair_basis/stair_basis.h"
#include "ksquad_point.glsl"
#include "ksquad_nonuniform.glsl"
layout(location = 0) flat in ivec4 die[];
layout(location = 1) flat in ivec2 die_levels[];
layout(location = 2) in vec3 die_corners[][4];
layout(location = 0) out vec2 trim_uv;
layout(location = 1) flat out int trim_surface;

vec3 lattice[NU_LATTICE][NU_LATTICE];
vec2 screen[NU_LATTICE][NU_LATTICE];
float epsilon, eta;  // mode's, times the surface's threshold_scale (vk-thresholds=surface)

// eq. 4 for the cell with corner (a, b) and `step` lattice steps a side.
bool linear_cell_passes(int a, int b, int step) {
  const int h = step / 2;
  const vec3 c00 = lattice[a][b], c10 = lattice[a + step][b], c01 = lattice[a][b + step],
             c11 = lattice[a + step][b + step];
  const ivec2 at[5] = ivec2[5](ivec2(a + h, b + h), ivec2(a + h, b), ivec2(a, b + h),
                               ivec2(a + step, b + h), ivec2(a + h, b + step));
  // the centre lies on the strip's diagonal (0,1)-(1,0) (main: the emission order)
  const vec3 linear[5] = vec3[5](0.5 * (c01 + c10), 0.5 * (c00 + c10),
                                 0.5 * (c00 + c01), 0.5 * (c10 + c11), 0.5 * (c01 + c11));
  for (int k = 0; k < 5; ++k)
    if (!(distance(screen[at[k].x][at[k].y], pixels(linear[k])) < epsilon)) return false;
  return true;
}

int linear_depth() {
  for (int d = 0; d < NU_DEPTH; ++d) {
    const int step = (NU_LATTICE - 1) >> d;
    bool pass = true;
    for (int a = 0; a < NU_LATTICE - 1; a += step)
      for (int b = 0; b < NU_LATTICE - 1; b += step) pass = pass && linear_cell_passes(a, b, step);
    if (pass) return d;
  }
  return NU_DEPTH;
}

// eq. 5 on the sides of `f`.
int boundary_depth(int f) {
  if (f == 0) return 0;
  const int last = NU_LATTICE - 1;
  for (int d = 0; d < NU_DEPTH; ++d) {
    const int step = last >> d;
    bool pass = true;
    for (int k = 0; k < last; k += step) {
      // side 0: u = lo (a = 0), 1: v = lo (b = 0), 2: u = hi, 3: v = hi
      if ((f & 1) != 0) pass = pass && distance(screen[0][k], screen[0][k + step]) < eta;
      if ((f & 2) != 0) pass = pass && distance(screen[k][0], screen[k + step][0]) < eta;
      if ((f & 4) != 0)
        pass = pass && distance(screen[last][k], screen[last][k + step]) < eta;
      if ((f & 8) != 0)
        pass = pass && distance(screen[k][last], screen[k + step][last]) < eta;
    }
    if (pass) return d;
  }
  return NU_DEPTH;
}

// 1: outside the frustum, 2: a back face, 0: visible.
int culled() {
  vec4 c[4];
  for (int k = 0; k < 4; ++k) c[k] = mode.view_projection * vec4(die_corners[0][k], 1.0);
  bvec4 out_plane[6];
  for (int k = 0; k < 4; ++k) {
    out_plane[0][k] = c[k].x > c[k].w;
    out_plane[1][k] = c[k].x < -c[k].w;
    out_plane[2][k] = c[k].y > c[k].w;
    out_plane[3][k] = c[k].y < -c[k].w;
    out_plane[4][k] = c[k].z < 0.0;
    out_plane[5][k] = c[k].z > c[k].w;
  }
  for (int p = 0; p < 6; ++p)
    if (all(out_plane[p])) return 1;
  if (c[0].w <= 0.0 || c[1].w <= 0.0 || c[2].w <= 0.0 || c[3].w <= 0.0) return 0;
  vec2 q[4];
  // the quad's order: (0,0) (1,0) (1,1) (0,1)
  const int order[4] = int[4](0, 1, 3, 2);
  for (int k = 0; k < 4; ++k) q[k] = c[order[k]].xy / c[order[k]].w * 0.5 * mode.viewport;
  float area = 0.0;
  for (int k = 0; k < 4; ++k) area += q[k].x * q[(k + 1) % 4].y - q[(k + 1) % 4].x * q[k].y;
  return area > 0.0 ? 2 : 0;
}

void main() {
  if (die[0].w == 0) return;
  const int patch_index = die[0].x, i = die[0].y, j = die[0].z;
  const int level_u = die_levels[0].x, level_v = die_levels[0].y;
  const int row = patch_index * PATCH_INTS;
  const int s = patches[row] * SURFACE_INTS;
  const int span_u = patches[row + 1], span_v = patches[row + 2];
  const int cu = patches[row + 3], cv = patches[row + 4];
  const int pu = DEGREE_U(s), pv = DEGREE_V(s);
  const int record = NU_KSDIE_INTS * ksdie_index(patch_index, i, j);
  // f: the KSDie's sides on the domain's sides (the knots and the domain ends are the same float
  // roundings of the same doubles), kept where the surface's side has no friend
  int sides = 0;
  if (i == 0 && SB_KNOT(cu, pu - 1) == surface_knot_u(s, 0)) sides |= 1;
  if (j == 0 && SB_KNOT(cv, pv - 1) == surface_knot_v(s, 0)) sides |= 2;
  if (i == level_u - 1 && SB_KNOT(cu, pu) == surface_knot_u(s, 1)) sides |= 4;
  if (j == level_v - 1 && SB_KNOT(cv, pv) == surface_knot_v(s, 1)) sides |= 8;
  const int f = sides & surfaces[s + 9];
  epsilon = mode.epsilon * threshold_scale(s);
  eta = mode.eta * threshold_scale(s);
  const int cull = culled();
  ksdice[record + 3] = f;
  if (cull != 0) {
    ksdice[record] = 1 + cull;
    ksdice[record + 1] = -1;
    ksdice[record + 2] = -1;
    return;
  }
  float us[NU_LATTICE], vs[NU_LATTICE];
  for (int a = 0; a < NU_LATTICE; ++a) {
    const float step = float(a) / float(NU_LATTICE - 1);  // exact: quarters
    us[a] = span_parameter(cu, pu, 0.0, 1.0, (float(i) + step) / float(level_u));
    vs[a] = span_parameter(cv, pv, 0.0, 1.0, (float(j) + step) / float(level_v));
  }
  const int last = NU_LATTICE - 1;
  for (int a = 0; a < NU_LATTICE; ++a)
    for (int b = 0; b < NU_LATTICE; ++b) {
      const bool corner = (a == 0 || a == last) && (b == 0 || b == last);
      lattice[a][b] = corner ? die_corners[0][(a == last ? 1 : 0) + (b == last ? 2 : 0)]
                             : ksquad_point(s, span_u, span_v, cu, cv, us[a], vs[b]);
      screen[a][b] = pixels(lattice[a][b]);
    }
  const int depth_linear = linear_depth(), depth_boundary = boundary_depth(f);
  ksdice[record] = 1;
  ksdice[record + 1] = depth_linear;
  ksdice[record + 2] = depth_boundary;
  const int depth = max(depth_linear, depth_boundary);
  const int step = last >> depth, n = 1 << depth;
  if (kRaster == 0) {
    for (int a = 0; a <= last; a += step)
      for (int b = 0; b <= last; b += step) {
        const int o = NU_VERTEX_FLOATS * (NU_LATTICE * NU_LATTICE * ksdie_index(patch_index, i, j) +
                                          a * NU_LATTICE + b);
        const float u = us[a], v = vs[b];
        positions[o] = u;
        positions[o + 1] = v;
        positions[o + 2] = lattice[a][b].x;
        positions[o + 3] = lattice[a][b].y;
        positions[o + 4] = lattice[a][b].z;
        if (mode.normals != 0) {
          // SB_KNOT(c, p) = x_i+1: the span's end knot belongs to the next span (row + 16..19)
          const bool u_end = u == SB_KNOT(cu, pu), v_end = v == SB_KNOT(cv, pv);
          const vec3 normal = ksquad_normal(s, u_end ? patches[row + 16] : span_u,
                                            v_end ? patches[row + 17] : span_v,
                                            u_end ? patches[row + 18] : cu,
                                            v_end ? patches[row + 19] : cv, u, v);
          positions[o + 5] = normal.x;
          positions[o + 6] = normal.y;
          positions[o + 7] = normal.z;
        }
      }
  }
  for (int b = 0; b < n; ++b) {
    for (int a = 0; a <= n; ++a)
      for (int side = 0; side < 2; ++side) {
        gl_Position = mode.view_projection * vec4(lattice[a * step][(b + side) * step], 1.0);
        trim_uv = vec2(us[a * step], vs[(b + side) * step]);
        trim_surface = patches[row];
        EmitVertex();
      }
    EndPrimitive();
  }
}
