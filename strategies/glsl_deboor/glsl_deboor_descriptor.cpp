// glsl-deboor: what it is, stated once for its entry in a build with OpenGL and its
// unavailable stub in a build without (strategies/registry.h, StrategyDescriptor).
#include "reference/validation.h"
#include "strategies/glsl_deboor/glsl_deboor.h"

namespace nurbs {

namespace {

constexpr const char* kSource =
    "002 §3.3 (Tan et al. 2012): de Boor in one fragment pass per direction, one quad per "
    "non-empty knot span with its knots as uniforms";

Capabilities deboor_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;  // one program per degree, compiled in prepare()
  c.rational = true;
  c.normals = false;  // 002 evaluates positions only
  c.fp32 = true;
  c.fp64 = false;  // RGBA32F textures, as in the paper
  c.sampling = SamplingModes{true, true, false};
  c.trims = true;  // 000 §4's trim texture, shared with gl-pingpong (strategies/trim_texture)
  // 000 §5's deforming surfaces: "only the control points" are sent again; knots, span runs,
  // parameters and trim textures depend on what a deforming scene keeps.
  c.updates_control_points = true;
  return c;
}

}  // namespace

StrategyDescriptor glsl_deboor_descriptor() {
  return {"glsl-deboor", kSource, "strategy", deboor_capabilities()};
}

}  // namespace nurbs
