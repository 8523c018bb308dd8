// glsl-deboor: Tan, Zhao & Lu 2012 (002 §3.3), one fragment pass per direction running de Boor's
// algorithm. Host: the parameters of each direction binned into non-empty knot spans
// (span_runs.h); device: per span one quad (a viewport over exactly its samples) with the span
// index and its 2p knots as uniforms, pass 1 = every control row as a curve in u, pass 2 = the
// pass-1 result reused as control points in v, divided by w. Float32 (RGBA32F textures, as in the
// paper), grid and span-grid sampling, positions only (the paper computes no normals).
//
// Several surfaces share one atlas per page: surface s owns the rows [row0_s, row0_s + count_v)
// of the control and pass-1 textures and [out0_s, out0_s + NV) of the output, so each pass is one
// render target for the whole scene; surfaces go to a new page when a texture side would exceed
// the device limit. Options (StrategyOptions.extra): "gl" = osmesa | egl (default egl); "tile" =
// largest texture side to use (default GL_MAX_TEXTURE_SIZE; small values exercise the paging);
// "trim-resolution", "trim-tolerance": 000 §4's trim texture, as gl-pingpong (strategies/
// trim_texture), which 002 does not have: glsl-deboor draws the same way, so it trims the same way;
// "deboor-draw" = per-span (default: one draw per span quad, 002's form) | instanced (one
// instanced draw per pass and degree, the per-span values in instance tables; the same points bit
// for bit). The record's device details say which ("draw").
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyDescriptor glsl_deboor_descriptor();
StrategyEntry glsl_deboor_entry();

}  // namespace nurbs
