#version 330 core
// 000 §4: a trim polygon's vertices, already mapped to clip space from the surface's (u, v)
// domain (u along x, v along y) on the host in double.
layout(location = 0) in vec2 position;
void main() {
  gl_Position = vec4(position, 0.0, 1.0);
}
