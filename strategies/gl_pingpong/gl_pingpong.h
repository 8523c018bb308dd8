// gl-pingpong: Krishnamurthy, Khardekar & McMains 2007 (000 §2-3), multi-pass basis evaluation
// on OpenGL. CPU: span search per evaluation parameter, knot-array / order-1 / span-index
// textures. GPU: k-1 order-raising ping-pong passes per direction, then k_u x k_v accumulation
// passes over the evaluation grid and the divide by w. Float32 only (the paper's textures), grid
// and span-grid sampling (tensor products of a u-list and a v-list), positions only.
//
// Options (StrategyOptions.extra): "gl" = osmesa | egl (default egl); "tile" = largest texture
// side to use (default: GL_MAX_TEXTURE_SIZE; smaller values exercise the tiling in tests);
// "trim-resolution" = R, "trim-tolerance" = T of 000 §4's trim texture (strategies/trim_texture:
// trimmed surfaces are classified by an R x R texture of their loops tessellated within T x the
// domain diagonal, and drawn with the outside discarded).
// The §2.3 RGBA packing of the basis passes is the second registry entry, gl-pingpong-packed, so
// that one `run` measures both ways side by side (also reachable as extra["packed"] = "1").
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyDescriptor gl_pingpong_descriptor(bool packed);
StrategyEntry gl_pingpong_entry();
StrategyEntry gl_pingpong_packed_entry();

}  // namespace nurbs
