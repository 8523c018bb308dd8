// The deforming-surface benchmark's motion (RPNS 2014, 003 §2 and its interactive-deformation
// experiments): every control point moves every frame. The paper gives no formula (its models are
// deformed "interactively"); we use a deterministic travelling wave, a pure function of
// (scene, frame), so every strategy and the reference see exactly the same frames.
//
// Frame f moves point P = (x, y, z) along z by
//   A sin(2 pi (x + y) / L + 2 pi f / 60),  A = diagonal / 50, L = diagonal / 2,
// with `diagonal` the control-point bounding-box diagonal of the undeformed scene (so the wave has
// the scene's scale and two crests across it; 60 frames per period). Weights, knots and degrees
// never change: only what update_control_points() re-uploads moves. Frame 0 is already displaced
// (sin of the phase alone), so "frame 0" is not "the undeformed scene".
#pragma once

#include "reference/surface.h"

namespace nurbs {

inline constexpr int kDeformingFramesPerPeriod = 60;

// Writes frame `frame` of `base` into `out` (any scene; its storage is reused when it already has
// base's sizes, so a frame loop does not allocate).
void deform_scene(const Scene& base, int frame, Scene& out);

// The same, returned.
Scene deformed_scene(const Scene& base, int frame);

}  // namespace nurbs
