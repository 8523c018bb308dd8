// gl-pingpong, GPU side: the compiled programs and one direction's basis chunk (000 §2.1):
// knot-array, order-1 and span-index textures uploaded once, then k-1 order-raising passes
// ping-ponging between two RGBA32F render targets.
#pragma once

#include <vector>

#include "strategies/gl_context/gl_program.h"
#include "strategies/gl_pingpong/knot_array.h"

namespace nurbs::gl_pingpong {

// The three fragment programs (basis order, accumulation, divide) for one packing, and the
// full-viewport triangle they are drawn with.
class Programs {
 public:
  Programs(gl::Context& context, bool packed);
  Programs(const Programs&) = delete;
  Programs& operator=(const Programs&) = delete;

  void draw() const;  // one full-viewport triangle into the bound target

  gl::Context& context;
  gl::Program basis, accumulate, divide;
  GLint basis_degree, basis_order, accumulate_a, accumulate_b;  // uniform locations

 private:
  gl::FullscreenTriangle triangle_;
};

class BasisChunk {
 public:
  BasisChunk(gl::Context& context, const ChunkInputs& inputs);

  // Runs `passes` order-raising passes from the order-1 texture (p of them give order k, fewer
  // give the intermediate orders). The order-1 texture is never written, so evaluate() can run
  // again without a re-upload; pass 1 reads it and the passes alternate between ping_[0] and
  // ping_[1] as Tex1/Tex2 do in the paper.
  void raise(const Programs& programs, int passes);

  const gl::Texture& result() const { return *result_; }
  const gl::Texture& first_index() const { return first_index_; }
  std::size_t bytes_uploaded() const { return bytes_uploaded_; }
  int count() const { return count_; }
  int degree() const { return degree_; }
  // result() read back: rows x (k + 1) texels x 4 floats (tests).
  std::vector<float> read_result() const;

 private:
  gl::Context* context_;
  int count_, rows_, degree_;
  gl::Texture knot_array_, order1_, first_index_;
  gl::Texture ping_[2];
  const gl::Texture* result_ = nullptr;
  std::size_t bytes_uploaded_ = 0;
};

}  // namespace nurbs::gl_pingpong
