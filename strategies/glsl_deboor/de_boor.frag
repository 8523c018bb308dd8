#version 330 core
// 002 §3.3.2-3.3.3: one fragment per output texel, drawn by a quad (viewport) that covers exactly
// the samples of one non-empty knot span; span and its 2p knots are uniforms, so no span search.
// direction 0 (pass 1): texel (a, row0 + j) = C_j(u_a), the control row j as a curve in u.
// direction 1 (pass 2): texel (b, out0 + a) = S(u_a, v_b), the pass-1 column a as a curve in v,
// divided by w. The output is laid out v along x so that its rows are runs of samples in the
// order the results want (a * nv + b): the read-back takes rows as they lie. db_de_boor is the single-source strategies/glsl_deboor/de_boor_source.h, which the
// host puts after the defines.
// INSTANCED (deboor-draw=instanced): the quads of a pass are one instanced draw (span_quad.vert)
// and the per-span values come from the instance tables instead of uniforms: the same values, so
// the same texels bit for bit.

uniform sampler2D control;     // homogeneous control points (pass 1) or curve points (pass 2)
uniform sampler2D parameters;  // row `surface_row`: the surface's u (pass 1) or v (pass 2) list
uniform int direction;
#if INSTANCED
flat in ivec4 span_indices;  // span_first, control_row0, output_row0, surface_row
flat in int span_instance;
// Instance i's 2p knots at texels (2p (i % SPANS_PER_ROW) + t, i / SPANS_PER_ROW).
uniform sampler2D span_knots;
#else
uniform int span_first;        // span - p: index of the first of the p+1 control points
uniform int control_row0;      // the surface's first row in the control / curve atlas
uniform int output_row0;       // pass 2: the surface's first row in the output atlas
uniform int surface_row;
uniform float knots[2 * DEGREE];  // K[t] = knots[span - p + 1 + t]
#endif

// One program per degree (DEGREE defined by the host): constant loop bounds let the compiler
// unroll the triangle and keep d[] in registers (a uniform degree costs llvmpipe ~10x: dynamic
// indexing of a local array goes through memory).
const int degree = DEGREE;

out vec4 result;

void main() {
#if INSTANCED
  int span_first = span_indices.x, control_row0 = span_indices.y;
  int output_row0 = span_indices.z, surface_row = span_indices.w;
  float knots[2 * DEGREE];
  ivec2 first_knot = ivec2(2 * degree * (span_instance % SPANS_PER_ROW),
                           span_instance / SPANS_PER_ROW);
  for (int t = 0; t < 2 * degree; ++t)
    knots[t] = texelFetch(span_knots, first_knot + ivec2(t, 0), 0).r;
#endif
  ivec2 at = ivec2(gl_FragCoord.xy);
  // Both passes draw their own direction's samples along x: u in pass 1, v in pass 2.
  float u = texelFetch(parameters, ivec2(at.x, surface_row), 0).r;
  int curve = at.y - output_row0;  // pass 2: the u sample, i.e. the pass-1 column
  vec4 d[DEGREE + 1];
  for (int j = 0; j <= degree; ++j)
    d[j] = direction == 0 ? texelFetch(control, ivec2(span_first + j, at.y), 0)
                          : texelFetch(control, ivec2(curve, control_row0 + span_first + j), 0);
  vec4 p = db_de_boor(degree, knots, u, d);
  result = direction == 0 ? p : vec4(p.xyz / p.w, 1.0);
}
