// 002 §4.3: Haar-wavelet levels of detail of one evaluated surface, on the GPU. Level 0 is the
// de Boor output (nu x nv, both even at every level used); level k+1 = the 2x2 averages of level
// k, by a row step then a column step (Fig 10 b), each writing averages and details through two
// render targets. Only the averages are transformed again in columns (the row details are kept
// as they are): the same information as the full 2D transform, one pass fewer per level.
#pragma once

#include <vector>

#include "strategies/gl_context/grid_renderer.h"
#include "strategies/glsl_deboor/deboor_evaluator.h"

namespace nurbs::glsl_deboor {

class HaarLod {
 public:
  // `levels` coarser levels of slot `slot` of `page` (sizes must halve exactly).
  HaarLod(gl::Context& context, const Page& page, const SurfaceSlot& slot, int levels);
  ~HaarLod();
  HaarLod(const HaarLod&) = delete;
  HaarLod& operator=(const HaarLod&) = delete;

  // Level k -> k+1 (k = 0 reads the de Boor output in place).
  void forward(int k);
  // Level k+1 and its details -> level k (k = 0 writes the level-0 copy).
  void inverse(int k);
  // Level k as (x, y, z) per point, ordered a * height + b like read_back. Level 0 is the
  // inverse-transformed copy (run inverse(0) first).
  std::vector<float> read(int k) const;
  // Where level k lies, for drawing it by vertex texture fetch (002 §4.3: levels are drawn from
  // the device, never read back). Level 0 is the de Boor output the levels were made from.
  gl::GridPoints grid(int k) const;
  int width(int k) const { return levels_[static_cast<std::size_t>(k)].width; }
  int height(int k) const { return levels_[static_cast<std::size_t>(k)].height; }

 private:
  struct Level {
    int width = 0, height = 0;
    gl::Texture points;                          // width x height (A_k)
    gl::Texture half, d_rows;                    // width/2 x height: after the row step
    gl::Texture d_columns;                       // width/2 x height/2
    GLuint row_targets = 0, column_targets = 0;  // MRT framebuffers (A, D)
  };
  GLuint two_targets(const gl::Texture& a, const gl::Texture& d);

  gl::Context& context_;
  const Page& page_;
  const SurfaceSlot& slot_;
  gl::Program forward_, inverse_;
  GLuint vertex_array_ = 0;
  std::vector<Level> levels_;
};

}  // namespace nurbs::glsl_deboor
