#version 450
// render(): a grey shaded by depth (the image is for timing and inspection, not lighting).
layout(location = 0) out vec4 color;

void main() { color = vec4(vec3(1.0 - 0.8 * gl_FragCoord.z), 1.0); }
