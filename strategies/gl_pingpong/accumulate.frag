#version 330 core
// 000 §3.1: one of the k_u x k_v accumulation passes. For control point (a, b) of each sample's
// sub-mesh: sum += N_u[a] * N_v[b] * P, P homogeneous (w x, w y, w z, w) from the n x m
// control-point texture at the sub-mesh's lower-left index (span index textures) plus (a, b).
// The running sum ping-pongs between two textures of the evaluation-grid tile.
//
// CPU counterpart: nurbs::surface_point_from_basis (reference/nurbs_math.h, A4.3), which sums
// row by row; here the (a, b) terms are added one pass at a time in the paper's order, a
// different rounding order but the same products.

uniform sampler2D previous;   // running homogeneous sum, one texel per sample (x: v, y: u)
uniform sampler2D control;    // texel (j, i) = homogeneous P_ij
uniform sampler2D basis_u;    // final basis rows of the tile's u parameters, column a
uniform sampler2D basis_v;
uniform isampler2D first_u;   // texel (0, row): span - p of the row's parameter
uniform isampler2D first_v;
uniform int a;
uniform int b;

out vec4 result;

float basis(sampler2D table, int column, int parameter) {
#if PACKED
  // §2.3: parameter 4r + c sits in channel c of row r; unpacking costs this pass extra work.
  return texelFetch(table, ivec2(column, parameter >> 2), 0)[parameter & 3];
#else
  return texelFetch(table, ivec2(column, parameter), 0).r;
#endif
}

void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  int iv = at.x, iu = at.y;
  int i = texelFetch(first_u, ivec2(0, iu), 0).r + a;
  int j = texelFetch(first_v, ivec2(0, iv), 0).r + b;
  vec4 p = texelFetch(control, ivec2(j, i), 0);
  result = texelFetch(previous, at, 0) + basis(basis_u, a, iu) * (basis(basis_v, b, iv) * p);
}
