#version 330 core
// One triangle covering the viewport (no vertex buffers): every pass of the GL strategies is a
// fragment program run once per texel of its render target.
void main() {
  vec2 corner = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1));
  gl_Position = vec4(corner - 1.0, 0.0, 1.0);
}
