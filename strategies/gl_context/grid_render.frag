#version 330 core
// Shaded by a headlight (002 draws a lit surface): the facet normal from the screen-space
// derivatives of the clip-space position (no normals are evaluated for drawing), Lambert with an
// ambient floor, opaque; tests judge coverage by alpha. 000 §4: on a trimmed surface a
// fragment whose (u, v) reads 0 in the trim texture is discarded (not blended away: the paper
// renders "only the parts of the surface that lie outside the trim curves" so that depth and
// draw order stay right). The lookup is the nearest texel (the texture's filtering), the same
// rule as the classify pass.
uniform int trimmed;
uniform sampler2D trim;
in vec2 trim_uv;
in vec3 clip_position;
out vec4 color;
void main() {
  if (trimmed != 0 && texture(trim, trim_uv).r < 0.5) discard;
  vec3 facet = cross(dFdx(clip_position), dFdy(clip_position));
  float lambert = dot(facet, facet) > 0.0 ? abs(normalize(facet).z) : 1.0;
  color = vec4(vec3(0.25 + 0.75 * lambert), 1.0);
}
