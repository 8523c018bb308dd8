// gl-pingpong, CPU side (000 §2.1, §3.1 step 1): for one parameter direction and one chunk of
// evaluation parameters, the span search, the knot-array texture, the order-1 basis texture and
// the span-index (lower-left control point) texture, laid out as the GPU passes read them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace nurbs::gl_pingpong {

struct ChunkInputs {
  int degree = 0;  // p; the order is k = p + 1
  int count = 0;   // evaluation parameters in the chunk
  bool packed = false;
  int channels = 1;  // floats per texel of knot_array and order1: 1, or 4 when packed
  int rows = 0;      // texture rows: count, or ceil(count / 4) when packed
  // rows x (2k + 1) texels: u, then knots[s - p .. s + p + 1], the 2k knots the non-zero basis
  // functions N_{s-p..s} of span s need (000 §2.1, Fig 2).
  std::vector<float> knot_array;
  // rows x (k + 1) texels: [0 ... 0 1 0] (000 Eq 4), N_s^0 = 1 in column p, column k a zero pad
  // so the last function's recursion reads a zero neighbour.
  std::vector<float> order1;
  std::vector<std::int32_t> first_index;  // count: s - p, the sub-mesh's lower-left index
  std::vector<int> spans;                 // count: s
  std::vector<float> parameters;          // count: the float parameters the GPU sees

  int knot_array_width() const { return 2 * (degree + 1) + 1; }
  int basis_width() const { return degree + 2; }
};

// Parameters [begin, end) of `parameters`, on a curve of `count` control points with float
// knots. The span search runs on the float parameter and float knots (nurbs::find_span), as a
// float32 evaluator sees them. Packed (000 §2.3, Fig 5): parameter 4r + c in channel c of row r;
// a last row with fewer than four repeats the chunk's last parameter in the spare channels.
ChunkInputs make_chunk_inputs(const std::vector<double>& parameters, std::size_t begin,
                              std::size_t end, int degree, int count,
                              const std::vector<float>& knots, bool packed);

}  // namespace nurbs::gl_pingpong
