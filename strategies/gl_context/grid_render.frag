#version 330 core
// Flat white: the images are compared by coverage, not shading. 000 §4: on a trimmed surface a
// fragment whose (u, v) reads 0 in the trim texture is discarded (not blended away: the paper
// renders "only the parts of the surface that lie outside the trim curves" so that depth and
// draw order stay right). The lookup is the nearest texel (the texture's filtering), the same
// rule as the classify pass.
uniform int trimmed;
uniform sampler2D trim;
in vec2 trim_uv;
out vec4 color;
void main() {
  if (trimmed != 0 && texture(trim, trim_uv).r < 0.5) discard;
  color = vec4(1.0);
}
