// The nonuniform mapping's records (ksquad_nonuniform.tese, ksquad_nonuniform.geom; host layout
// in ksquad_layout.h, read back by nonuniform_mapping.cpp). Per patch, the KSDie slots of its
// regular lattice of at most mode.max_level^2 KSDice, KSDie (i, j) in slot i * max_level + j.
//  * ksdice (binding 14): per KSDie NU_KSDIE_INTS ints: status (0 none, 1 emitted, 2 culled by
//    the view frustum, 3 culled as a back face), the eq. 4 depth, the eq. 5 depth (-1 when
//    culled), the f tag.
//  * positions (binding 5): per KSDie NU_LATTICE^2 vertex slots of NU_VERTEX_FLOATS floats (u, v,
//    x, y, z, nx, ny, nz), the KSDie's (NU_LATTICE x NU_LATTICE) lattice; a KSDie subdivided to
//    depth d writes every (4 >> d)-th one. Unwritten slots stay NaN (filled by the host).
layout(std430, set = 0, binding = 14) writeonly buffer Ksdice { int ksdice[]; };
#define NU_DEPTH 2
#define NU_LATTICE 5
#define NU_KSDIE_INTS 4
#define NU_VERTEX_FLOATS 8

// The KSDie (i, j) of patch `row_index` in a lattice of level_u x level_v.
int ksdie_index(int row_index, int i, int j) {
  return (row_index * mode.max_level + i) * mode.max_level + j;
}

// Pixels, as eq. 3's p() (ksquad.tesc project); w <= 0 (behind the eye) -> +inf.
vec2 pixels(vec3 p) {
  const vec4 c = mode.view_projection * vec4(p, 1.0);
  if (c.w <= 0.0) return vec2(1.0 / 0.0);
  return c.xy / c.w * 0.5 * mode.viewport;
}
