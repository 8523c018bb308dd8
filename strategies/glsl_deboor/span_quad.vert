#version 330 core
// The instanced form of glsl-deboor's span quads (option deboor-draw=instanced): one draw per
// pass and degree, instance i = span run i. What the per-span form sets per draw (a viewport over
// the run's texels, the span's indices as uniforms) comes from the instance table instead, so the
// fragment shader computes every texel from the same values either way.
// spans, instance i at texels (2 (i % SPANS_PER_ROW), i / SPANS_PER_ROW) and the one after it:
//   (x, y, width, height) of the run's rectangle in the render target, in texels;
//   (span - p, control_row0, output_row0, surface_row) as de_boor.frag's uniforms of that name.
// Floats hold them exactly (all below 2^24).

uniform sampler2D spans;
uniform ivec2 target_size;

flat out ivec4 span_indices;
flat out int span_instance;

// Two triangles over the rectangle: corner bit 0 = right, bit 1 = top.
const int corners[6] = int[6](0, 1, 2, 1, 3, 2);

void main() {
  ivec2 at = ivec2(2 * (gl_InstanceID % SPANS_PER_ROW), gl_InstanceID / SPANS_PER_ROW);
  vec4 rect = texelFetch(spans, at, 0);
  span_indices = ivec4(texelFetch(spans, at + ivec2(1, 0), 0));
  span_instance = gl_InstanceID;
  int corner = corners[gl_VertexID];
  vec2 texel = rect.xy + vec2(float(corner & 1), float(corner >> 1)) * rect.zw;
  // Edges on texel boundaries: a texel is drawn exactly when its centre lies in the run.
  gl_Position = vec4(texel / vec2(target_size) * 2.0 - 1.0, 0.0, 1.0);
}
