#version 330 core
// 000 §4, "looked up per evaluated sample": the mask texel (b, a) of sample (u_a, v_b) takes the
// trim texel holding that sample. The sample table (row 0: u samples, row 1: v samples) carries
// each sample's texel index in .r, chosen on the host in double (the texel whose square contains
// the sample, i.e. the nearest texel centre), so float rounding cannot move a lookup.
uniform sampler2D trim;
uniform sampler2D parameters;
out vec4 inside;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);  // x = v index b, y = u index a
  int iu = int(texelFetch(parameters, ivec2(p.y, 0), 0).r);
  int iv = int(texelFetch(parameters, ivec2(p.x, 1), 0).r);
  inside = vec4(texelFetch(trim, ivec2(iu, iv), 0).r);
}
