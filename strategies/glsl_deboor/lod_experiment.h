// 002 §4.3 / Fig 15 as a measurement: changing the level of detail of one evaluated surface by
// one Haar step (forward: one level coarser; inverse: one level finer) versus evaluating the
// surface again at the new resolution with the same de Boor passes, alone and as the paper's
// baseline does it (002 §2 on Krishnamurthy's LOD: re-evaluate, transfer the points, regenerate
// the index data); what each level costs to draw from the device; and how far each coarser
// level's averages lie from the surface. GL-free interface: `nurbsbench lod` calls it in every
// build, and without OpenGL it throws the reason.
#pragma once

#include <optional>
#include <vector>

#include "reference/surface.h"
#include "strategies/strategy.h"

namespace nurbs::glsl_deboor {

// One grid drawn as triangles straight from its texture (002 §4.2 vertex texture fetch) into a
// kLodRenderSize² image, with the index buffer of its size built beforehand, as the paper's
// display list is.
struct LodDraw {
  std::vector<double> seconds;  // each repetition (after a warm-up), host clock around glFinish
  int index_elements = 0;       // of the index buffer drawn, as GL holds it
  long drawn_pixels = 0;        // pixels the grid covers (background: alpha 0)
  std::optional<RenderedImage> picture;  // only when asked for
};
// The size glsl-deboor's render phase draws (`run`'s render column), so the two compare.
inline constexpr int kLodRenderSize = 512;

struct LodLevel {
  int level = 0;  // 1 = the 2x2 block averages of the evaluated grid, 2 = of level 1...
  int width = 0, height = 0;
  // Largest distance (model units) from a level-k average to the surface point at the mean of
  // the block's grid parameters: wavelet averages are not surface points.
  double max_distance = 0;
  LodDraw draw;
};

struct LodMeasurement {
  DeviceInfo device;
  // Seconds of each repetition (after a warm-up), host clock around glFinish.
  std::vector<double> coarser_by_haar, coarser_by_reevaluation;  // nu x nv -> nu/2 x nv/2
  std::vector<double> finer_by_haar, finer_by_reevaluation;      // nu/2 x nv/2 -> nu x nv
  // The same changes as Fig 15's baseline pays them: evaluate, read back, upload as the vertex
  // buffer, regenerate and upload the new size's index buffer.
  std::vector<double> coarser_by_full_reevaluation, finer_by_full_reevaluation;
  int coarser_index_elements = 0, finer_index_elements = 0;  // of those rebuilt index buffers
  LodDraw full_draw;                                         // the nu x nv grid (level 0)
  std::vector<LodLevel> levels;                              // 1..levels
};

// Surface 0 of `scene` on the nu x nv grid; nu and nv must be divisible by 2^levels (callers
// check; a violation throws RefusedError). `options` carries the GL platform ("gl");
// `pictures`: keep each draw's image.
LodMeasurement measure_lod(const Scene& scene, int nu, int nv, int levels, int repetitions,
                           const StrategyOptions& options, bool pictures = false);

}  // namespace nurbs::glsl_deboor
