#version 330 core
// 000 §2.1: raise the basis functions by one order. Reads the previous order's texture and the
// knot array, writes the next order (ping-pong through an FBO). One texel = one basis function
// N_{s-p+j} (column j) of one evaluation parameter (row), s its span, p the final degree.
//
// The arithmetic mirrors nurbs::basis_functions (reference/nurbs_math.h, Piegl & Tiller A2.2)
// step for step, so that order by order the texture equals the CPU's float basis:
//   temp = N_i^{d-1} / (right + left),  N_{i-1}^d += right * temp,  N_i^d = left * temp
// i.e. N_i^d = (u - u_i) * [N_i^{d-1} / ((u_{i+d} - u) + (u - u_i))]
//            + (u_{i+d+1} - u) * [N_{i+1}^{d-1} / ((u_{i+d+1} - u) + (u - u_{i+1}))].
// Outside the triangle A2.2 computes, repeated knots make 0/0; the paper (§2.3) takes it as 0 and
// checks explicitly rather than trusting the driver, per channel in the packed layout.
//
// PACKED 0: one parameter per row, value in .r (the other channels unused: the waste §2.3
// removes). PACKED 1 (§2.3, Fig 5): four parameters per row, one per channel.

uniform sampler2D knot_array;  // row: texel 0 = u, texels 1..2k = knots[s-p .. s+p+1]
uniform sampler2D previous;    // order d (degree d-1) basis; column k is a zero pad
uniform int degree;            // d, the degree this pass produces (1..p)
uniform int order;             // k = p + 1
// Where the chunk's columns start: 0 in textures of its own, its band in an atlas holding every
// surface's chunks side by side (rows are shared: a chunk's row r is row r of every texture).
uniform int basis_x0;
uniform int knot_x0;

out vec4 result;

#if PACKED
#define VALUE vec4
VALUE channel(vec4 texel) { return texel; }
vec4 store(VALUE value) { return value; }
VALUE ratio_or_zero(VALUE n, VALUE d) {
  VALUE r;
  for (int c = 0; c < 4; ++c) r[c] = d[c] != 0.0 ? n[c] / d[c] : 0.0;
  return r;
}
#else
#define VALUE float
VALUE channel(vec4 texel) { return texel.r; }
vec4 store(VALUE value) { return vec4(value, 0.0, 0.0, 0.0); }
VALUE ratio_or_zero(VALUE n, VALUE d) { return d != 0.0 ? n / d : 0.0; }
#endif

VALUE knot(int m, int row) {
  return channel(texelFetch(knot_array, ivec2(knot_x0 + 1 + m, row), 0));
}

void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  int j = at.x - basis_x0, row = at.y;
  if (j >= order) {  // the pad column stays zero: N_{s+1} is not supported on span s
    result = vec4(0.0);
    return;
  }
  VALUE u = channel(texelFetch(knot_array, ivec2(knot_x0, row), 0));
  VALUE n_i = channel(texelFetch(previous, ivec2(basis_x0 + j, row), 0));
  VALUE n_next = channel(texelFetch(previous, ivec2(basis_x0 + j + 1, row), 0));
  // u_i is knot(j): i = s - p + j and the row starts at knots[s - p].
  VALUE left = u - knot(j, row);
  VALUE left_next = u - knot(j + 1, row);
  VALUE right_i = knot(j + degree, row) - u;
  VALUE right = knot(j + degree + 1, row) - u;
  VALUE from_i = left * ratio_or_zero(n_i, right_i + left);
  VALUE from_next = right * ratio_or_zero(n_next, right + left_next);
  result = store(from_i + from_next);
}
