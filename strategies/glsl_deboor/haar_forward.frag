#version 330 core
// 002 §4.3.2, Fig 11: one Haar step along rows (direction 0) or columns (direction 1): texel i of
// the half-size outputs gets A = (a_2i + a_2i+1) / 2 (render target 0) and D = (a_2i - a_2i+1) / 2
// (render target 1), the paper's shader with texelFetch in place of texture2DRect.
uniform sampler2D level;
uniform ivec2 origin;  // where the level starts in `level` (the de Boor atlas for level 0)
uniform int direction;
layout(location = 0) out vec4 average;
layout(location = 1) out vec4 detail;
void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  ivec2 step = direction == 0 ? ivec2(1, 0) : ivec2(0, 1);
  ivec2 first = origin + (direction == 0 ? ivec2(2 * at.x, at.y) : ivec2(at.x, 2 * at.y));
  vec4 a0 = texelFetch(level, first, 0);
  vec4 a1 = texelFetch(level, first + step, 0);
  average = 0.5 * (a0 + a1);
  detail = 0.5 * (a0 - a1);
}
