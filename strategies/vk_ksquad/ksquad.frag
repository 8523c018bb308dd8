#version 450
#extension GL_GOOGLE_include_directive : require
// render(): a grey shaded by depth (the image is for timing and inspection, not lighting), and
// direct trimming per fragment -- the paper's own use (Schollmeyer & Fröhlich 2009, §5): the
// fragment's interpolated (u, v) classified by td_classify of the single-source
// strategies/trim_direct/trim_direct.h (the compute pass's code), outside fragments discarded.
layout(location = 0) in vec2 trim_uv;
layout(location = 1) flat in int trim_surface;
layout(location = 0) out vec4 color;
layout(std430, set = 0, binding = 9) readonly buffer TdReals { float td_reals[]; };
layout(std430, set = 0, binding = 10) readonly buffer TdInts { int td_ints[]; };
// Per surface (vk_ksquad.cpp trim_surface_rows): tables base (-1: untrimmed), origin u, origin v
// and epsilon as float bits, iterations.
layout(std430, set = 0, binding = 11) readonly buffer TrimSurfaces { int trim_surfaces[]; };
#define TRIM_SURFACE_INTS 5

#include "../trim_direct/trim_direct.h"

void main() {
  const int t = TRIM_SURFACE_INTS * trim_surface;
  const int base = trim_surfaces[t];
  if (base >= 0) {
    const int packed = td_classify(base, trim_uv.x - intBitsToFloat(trim_surfaces[t + 1]),
                                   trim_uv.y - intBitsToFloat(trim_surfaces[t + 2]),
                                   intBitsToFloat(trim_surfaces[t + 3]), trim_surfaces[t + 4]);
    if ((packed & 1) == 0) discard;
  }
  color = vec4(vec3(1.0 - 0.8 * gl_FragCoord.z), 1.0);
}
