#version 330 core
// 001 eq. 4, last step: the rational divide of the homogeneous sums; with NORMALS, the first
// partial derivatives by the quotient rule (S_u = (A_u - w_u S) / w) and the unit normal
// S_u x S_v, zero where it is float rounding noise (as the reference leaves no T-spline normal
// where the derivatives do not resolve one).
uniform sampler2D sum;
#if NORMALS
uniform sampler2D sum_u;
uniform sampler2D sum_v;
#endif

layout(location = 0) out vec4 position;
#if NORMALS
layout(location = 1) out vec4 normal;
#endif

void main() {
  ivec2 at = ivec2(gl_FragCoord.xy);
  vec4 s = texelFetch(sum, at, 0);
  vec3 p = s.xyz / s.w;
  position = vec4(p, 1.0);
#if NORMALS
  vec4 a = texelFetch(sum_u, at, 0);
  vec4 b = texelFetch(sum_v, at, 0);
  vec3 su = (a.xyz - a.w * p) / s.w;
  vec3 sv = (b.xyz - b.w * p) / s.w;
  vec3 n = cross(su, sv);
  float len = length(n);
  // reference/nurbs_math.h normalize_if_resolved's rule with float's epsilon (2^-23).
  float scale = length(su) + length(sv);
  bool resolved = len > 1024.0 * 1.1920929e-7 * scale * scale;
  normal = vec4(resolved ? n / len : vec3(0.0), 0.0);
#endif
}
