// glu-nurbs: OpenGL's own NURBS tessellator (GLU's gluNurbsSurface in GLU_NURBS_TESSELLATOR
// mode), the baseline of 000's Fig 8. GLU picks its own samples: GLU_DOMAIN_DISTANCE with the
// step set from the requested grid's density, one degree-1 GL_MAP2_TEXTURE_COORD_2 surface over
// the parameter domain evaluated alongside so that each captured vertex carries its (u, v).
// float32 only (GLU's API is float), grid requests only, positions only (GLU's normals are per
// Bezier patch: see glu_nurbs_capabilities); read_back returns the distinct vertices it produced
// as an explicit (u, v) list (SurfaceSamples::tensor == false), measured against the reference
// there. Runs on the CPU, one thread, and needs no GL context. Built when GLU (libglu1-mesa-dev)
// is installed.
// Trimmed surfaces are trimmed natively: each loop goes to GLU between gluBeginTrim/gluEndTrim,
// degree-1 curves as gluPwlCurve, others as gluNurbsCurve (GLU_MAP1_TRIM_2, or _3 with
// homogeneous points when rational), oriented first for GLU's rule (the left of each curve is
// kept: outer loops counter-clockwise, holes clockwise) from the loop's nesting depth and signed
// area, so that GLU keeps the scene's even-odd face. GLU tessellates only the face and classifies
// nothing: its records say "untrimmed" (no per-sample classification, no misclassification
// figure), their errors over its vertices the reference puts inside, and its timing is that of
// the trimmed tessellation (000's Fig 8 baseline). Trim curves above degree 7 are refused: GLU's
// trim tessellator reads past a table of orders 1..8 for them and crashes (glu_nurbs.cpp).
#pragma once

#include "strategies/registry.h"

namespace nurbs {

StrategyEntry glu_nurbs_entry();

}  // namespace nurbs
