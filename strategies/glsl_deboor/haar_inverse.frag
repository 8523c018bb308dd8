#version 330 core
// 002 §4.3.2: the inverse Haar step, a_2i = A + D, a_2i+1 = A - D, along rows (direction 0) or
// columns (direction 1).
uniform sampler2D average;
uniform sampler2D detail;
uniform int direction;
out vec4 result;
void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  int i = direction == 0 ? at.x : at.y;
  ivec2 half_at = direction == 0 ? ivec2(at.x / 2, at.y) : ivec2(at.x, at.y / 2);
  vec4 a = texelFetch(average, half_at, 0);
  vec4 d = texelFetch(detail, half_at, 0);
  result = (i & 1) == 0 ? a + d : a - d;
}
