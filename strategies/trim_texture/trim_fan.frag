#version 330 core
// 000 §4: every fan triangle writes 1; the blend function ONE_MINUS_DST_COLOR, ZERO turns that
// into dst' = 1 - dst, so a texel toggles once per triangle covering its centre and ends 1 exactly
// when the count is odd.
out vec4 color;
void main() {
  color = vec4(1.0);
}
