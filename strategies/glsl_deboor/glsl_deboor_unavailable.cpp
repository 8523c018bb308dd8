// glsl-deboor when the build has no OpenGL (no OSMesa/EGL development packages, or
// NURBSBENCH_CPU_ONLY): still registered, so `list` and results say why it did not run.
#include <stdexcept>
#include <string>

#include "strategies/glsl_deboor/glsl_deboor.h"
#include "strategies/glsl_deboor/lod_experiment.h"

namespace nurbs {

StrategyEntry glsl_deboor_entry() {
  return unavailable_entry(glsl_deboor_descriptor(), NURBSBENCH_GL_MISSING);
}

namespace glsl_deboor {

LodMeasurement measure_lod(const Scene&, int, int, int, int, const StrategyOptions&, bool) {
  throw std::runtime_error(std::string("unavailable: ") + NURBSBENCH_GL_MISSING);
}

}  // namespace glsl_deboor
}  // namespace nurbs
