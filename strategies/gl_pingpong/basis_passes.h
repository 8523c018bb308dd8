// gl-pingpong, GPU side: the compiled programs and one direction's basis chunk (000 §2.1):
// knot-array, order-1 and span-index textures uploaded once, then k-1 order-raising passes
// ping-ponging between two RGBA32F render targets.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "strategies/gl_context/gl_program.h"
#include "strategies/gl_pingpong/knot_array.h"

namespace nurbs::gl_pingpong {

// 000 §2.1's order-raising program (basis_order.frag) for one packing, and the full-viewport
// triangle its passes are drawn with. Shared by the surface path (Programs) and the curve path
// (curve_eval.h).
class BasisProgram {
 public:
  BasisProgram(gl::Context& context, bool packed);
  BasisProgram(const BasisProgram&) = delete;
  BasisProgram& operator=(const BasisProgram&) = delete;

  void draw() const;  // one full-viewport triangle into the bound target

  gl::Context& context;
  gl::Program program;
  GLint degree, order, basis_x0, knot_x0;  // uniform locations

 private:
  gl::FullscreenTriangle triangle_;
};

// The surface path's programs (000 §3.1): the basis passes, the accumulation, the divide.
class Programs {
 public:
  Programs(gl::Context& context, bool packed);
  Programs(const Programs&) = delete;
  Programs& operator=(const Programs&) = delete;

  void draw() const { basis.draw(); }

  gl::Context& context;
  BasisProgram basis;
  gl::Program accumulate, divide;
  // accumulate.frag's uniform locations
  GLint accumulate_a, accumulate_b, origin, control_origin, place_u, place_v;
};

class BasisChunk {
 public:
  BasisChunk(gl::Context& context, const ChunkInputs& inputs);

  // Runs `passes` order-raising passes from the order-1 texture (p of them give order k, fewer
  // give the intermediate orders). The order-1 texture is never written, so evaluate() can run
  // again without a re-upload; pass 1 reads it and the passes alternate between ping_[0] and
  // ping_[1] as Tex1/Tex2 do in the paper.
  void raise(const BasisProgram& program, int passes);

  const gl::Texture& result() const { return *result_; }
  const gl::Texture& first_index() const { return first_index_; }
  // The same s - p per parameter, kept on the host for a CPU gather (000 §2.2's control array).
  const std::vector<std::int32_t>& first_indices() const { return first_indices_; }
  std::size_t bytes_uploaded() const { return bytes_uploaded_; }
  int count() const { return count_; }
  int degree() const { return degree_; }
  // result() read back: rows x (k + 1) texels x 4 floats (tests).
  std::vector<float> read_result() const;

 private:
  gl::Context* context_;
  int count_, rows_, degree_;
  gl::Texture knot_array_, order1_, first_index_;
  std::vector<std::int32_t> first_indices_;
  gl::Texture ping_[2];
  const gl::Texture* result_ = nullptr;
  std::size_t bytes_uploaded_ = 0;
};

// Every surface's basis chunks, both directions, in one set of textures: a chunk's knot-array,
// order-1 and first-index rows go up in one upload per kind of data (not three per chunk), and its
// passes draw its rectangle of two shared ping-pong targets. Chunks are laid in bands of `side`
// rows side by side (band b: basis columns b * basis_width, knot columns b * knot_width), a
// chunk's rows the same rows of the knot, order-1 and ping-pong textures; the first indices (a row
// per parameter, also when packed) are banded the same way in a texture of their own. The passes
// are 000 §2.1's, chunk by chunk as BasisChunk draws them; only where the texels lie differs.
class BasisAtlas {
 public:
  BasisAtlas() = default;
  // Throws RefusedError when the bands do not fit GL_MAX_TEXTURE_SIZE. `bytes` grows by what was
  // sent.
  BasisAtlas(gl::Context& context, const std::vector<ChunkInputs>& chunks, bool packed, int side,
             std::size_t& bytes);

  // Chunk `c`'s `passes` order-raising passes from its order-1 rows (BasisChunk::raise).
  void raise(const BasisProgram& program, std::size_t c, int passes) const;

  // The texture holding chunk `c`'s final basis (after raise with its degree).
  const gl::Texture& result(std::size_t c) const;
  const gl::Texture& first_index() const { return first_index_; }
  // accumulate.frag's place of chunk `c`: first basis column and row, first-index column and row.
  std::array<int, 4> place(std::size_t c) const {
    const Place& p = places_[c];
    return {p.band * basis_width_, p.row0, p.first_band, p.first_row0};
  }
  std::size_t size() const { return places_.size(); }

 private:
  struct Place {
    int band = 0, row0 = 0, rows = 0, degree = 0;
    int first_band = 0, first_row0 = 0;  // in the first-index texture
  };
  gl::Context* context_ = nullptr;
  std::vector<Place> places_;
  int basis_width_ = 0, knot_width_ = 0;
  gl::Texture knot_array_, order1_, first_index_;
  gl::Texture ping_[2];
};

// One direction's parameters cut into chunks of at most `tile` (a texture's rows), each
// uploaded as a BasisChunk; begins[c] is chunk c's first parameter, `bytes` grows by what was sent.
std::vector<BasisChunk> upload_chunks(gl::Context& context, const std::vector<double>& parameters,
                                      int degree, int count, const std::vector<float>& knots,
                                      bool packed, int tile, std::vector<std::size_t>& begins,
                                      std::size_t& bytes);

}  // namespace nurbs::gl_pingpong
