#version 330 core
// Flat white: the renderer's images are compared by coverage, not shading.
out vec4 color;
void main() {
  color = vec4(1.0);
}
