#version 330 core
// 000 §3.1: one of the k_u x k_v accumulation passes. For control point (a, b) of each sample's
// sub-mesh: sum += N_u[a] * N_v[b] * P, P homogeneous (w x, w y, w z, w) from the n x m
// control-point texture at the sub-mesh's lower-left index (span index textures) plus (a, b).
// The running sum ping-pongs between two textures of the evaluation-grid tile.
//
// Every surface's data lies in shared textures (one upload per kind of data, not per surface): the
// tile is a rectangle of the sum atlas at `origin`, the control net a rectangle of the control
// atlas at `control_origin`, each direction's chunk a band of the basis atlas (`place_*`).
//
// CPU counterpart: nurbs::surface_point_from_basis (reference/nurbs_math.h, A4.3), which sums
// row by row; here the (a, b) terms are added one pass at a time in the paper's order, a
// different rounding order but the same products.

uniform sampler2D previous;   // running homogeneous sum, one texel per sample (x: v, y: u)
uniform sampler2D control;    // texel control_origin + (j, i) = homogeneous P_ij
uniform sampler2D basis_u;    // final basis rows of the tile's u parameters, column a
uniform sampler2D basis_v;
uniform isampler2D first_u;   // texel place.zw + (0, q): span - p of parameter q of the chunk
uniform isampler2D first_v;
uniform int a;
uniform int b;
uniform ivec2 origin;          // the tile's first texel in the sum textures
uniform ivec2 control_origin;  // P_00 in the control texture
uniform ivec4 place_u;  // the u chunk: first basis column and row, first-index column and row
uniform ivec4 place_v;

out vec4 result;

float basis(sampler2D table, ivec4 place, int column, int parameter) {
#if PACKED
  // §2.3: parameter 4r + c sits in channel c of row r; unpacking costs this pass extra work.
  return texelFetch(table, ivec2(place.x + column, place.y + (parameter >> 2)), 0)[parameter & 3];
#else
  return texelFetch(table, ivec2(place.x + column, place.y + parameter), 0).r;
#endif
}

void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  int iv = at.x - origin.x, iu = at.y - origin.y;
  int i = texelFetch(first_u, place_u.zw + ivec2(0, iu), 0).r + a;
  int j = texelFetch(first_v, place_v.zw + ivec2(0, iv), 0).r + b;
  vec4 p = texelFetch(control, control_origin + ivec2(j, i), 0);
  result = texelFetch(previous, at, 0) +
           basis(basis_u, place_u, a, iu) * (basis(basis_v, place_v, b, iv) * p);
}
