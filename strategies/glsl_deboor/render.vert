#version 330 core
// 002 §4.2: rendering without read-back. VERTEX_FETCH 1: the static index buffer's index k is
// turned into the evaluated point by vertex texture fetch from the de Boor output atlas
// (texel (a, output_row0 + b), k = b * nu + a). VERTEX_FETCH 0: the "traditional" path of §4.1,
// the same points read back to the host and re-uploaded as a vertex buffer.
uniform mat4 mvp;
#if VERTEX_FETCH
uniform sampler2D points;
uniform int nu;
uniform int output_row0;
#else
layout(location = 0) in vec3 position;
#endif

void main() {
#if VERTEX_FETCH
  int k = gl_VertexID;
  vec3 position = texelFetch(points, ivec2(k % nu, output_row0 + k / nu), 0).xyz;
#endif
  gl_Position = mvp * vec4(position, 1.0);
}
