// 002 §4.3 / Fig 15 as a measurement: changing the level of detail of one evaluated surface by
// one Haar step (forward: one level coarser; inverse: one level finer) versus evaluating the
// surface again at the new resolution with the same de Boor passes; and how far each coarser
// level's averages lie from the surface. GL-free interface: `nurbsbench lod` calls it in every
// build, and without OpenGL it throws the reason.
#pragma once

#include <vector>

#include "reference/surface.h"
#include "strategies/strategy.h"

namespace nurbs::glsl_deboor {

struct LodLevel {
  int level = 0;  // 1 = the 2x2 block averages of the evaluated grid, 2 = of level 1...
  int width = 0, height = 0;
  // Largest distance (model units) from a level-k average to the surface point at the mean of
  // the block's grid parameters: wavelet averages are not surface points.
  double max_distance = 0;
};

struct LodMeasurement {
  DeviceInfo device;
  // Seconds of each repetition (after a warm-up), host clock around glFinish.
  std::vector<double> coarser_by_haar, coarser_by_reevaluation;  // nu x nv -> nu/2 x nv/2
  std::vector<double> finer_by_haar, finer_by_reevaluation;      // nu/2 x nv/2 -> nu x nv
  std::vector<LodLevel> levels;                                  // 1..levels
};

// Surface 0 of `scene` on the nu x nv grid; nu and nv must be divisible by 2^levels (callers
// check; a violation throws RefusedError). `options` carries the GL platform ("gl").
LodMeasurement measure_lod(const Scene& scene, int nu, int nv, int levels, int repetitions,
                           const StrategyOptions& options);

}  // namespace nurbs::glsl_deboor
