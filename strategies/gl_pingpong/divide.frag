#version 330 core
// 000 §3.1, last step: from the homogeneous sum to the point, (x, y, z) / w (A4.3's divide).
uniform sampler2D sum;
out vec4 result;
void main() {
  vec4 s = texelFetch(sum, ivec2(gl_FragCoord.xy), 0);
  result = vec4(s.xyz / s.w, 1.0);
}
