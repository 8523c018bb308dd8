// gl-pingpong and gl-pingpong-packed: what it is, stated once for its entry in a build with OpenGL
// and its unavailable stub in a build without (strategies/registry.h, StrategyDescriptor).
#include "reference/validation.h"
#include "strategies/gl_pingpong/gl_pingpong.h"

namespace nurbs {

namespace {

constexpr const char* kSource =
    "000 §2-3 (Krishnamurthy et al. 2007): knot-array texture, ping-pong basis passes, "
    "k_u x k_v accumulation passes";

Capabilities pingpong_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;  // any order: one program, k-1 passes, 2k+1 knot-array columns
  c.rational = true;
  c.normals = false;  // the paper evaluates positions only
  c.fp32 = true;
  c.fp64 = false;  // RGBA32F textures, as in the paper
  c.sampling = SamplingModes{true, true, false};
  c.trims = true;  // 000 §4's trim texture (strategies/trim_texture)
  // 000 §5: for a deforming surface "only the control points" are sent again; the knot arrays,
  // basis chunks, trim textures and targets depend on knots, samples and trims, which a deforming
  // scene keeps.
  c.updates_control_points = true;
  return c;
}

}  // namespace

StrategyDescriptor gl_pingpong_descriptor(bool packed) {
  return {packed ? "gl-pingpong-packed" : "gl-pingpong", kSource, "strategy",
          pingpong_capabilities()};
}

}  // namespace nurbs
