#include "strategies/gl_pingpong/knot_array.h"

#include "reference/nurbs_math.h"

namespace nurbs::gl_pingpong {

ChunkInputs make_chunk_inputs(const std::vector<double>& parameters, std::size_t begin,
                              std::size_t end, int degree, int count,
                              const std::vector<float>& knots, bool packed) {
  ChunkInputs in;
  in.degree = degree;
  in.count = static_cast<int>(end - begin);
  in.packed = packed;
  in.channels = packed ? 4 : 1;
  in.rows = packed ? (in.count + 3) / 4 : in.count;
  const int order = degree + 1;
  const int kw = in.knot_array_width(), bw = in.basis_width();
  in.knot_array.assign(static_cast<std::size_t>(in.rows) * kw * in.channels, 0.0f);
  in.order1.assign(static_cast<std::size_t>(in.rows) * bw * in.channels, 0.0f);
  for (int q = 0; q < in.count; ++q) {
    const float u = static_cast<float>(parameters[begin + static_cast<std::size_t>(q)]);
    const int s = find_span(degree, count, knots.data(), u);
    in.parameters.push_back(u);
    in.spans.push_back(s);
    in.first_index.push_back(s - degree);
  }
  // Slots beyond the chunk's end in a packed last row repeat the last parameter (finite values,
  // never read back).
  const int slots = in.rows * in.channels;
  for (int slot = 0; slot < slots; ++slot) {
    const int q = slot < in.count ? slot : in.count - 1;
    const int row = slot / in.channels, c = slot % in.channels;
    const float u = in.parameters[static_cast<std::size_t>(q)];
    const int s = in.spans[static_cast<std::size_t>(q)];
    auto knot_texel = [&](int column) -> float& {
      return in.knot_array[(static_cast<std::size_t>(row) * kw + column) * in.channels + c];
    };
    knot_texel(0) = u;
    for (int m = 0; m < 2 * order; ++m)
      knot_texel(1 + m) = knots[static_cast<std::size_t>(s - degree + m)];
    in.order1[(static_cast<std::size_t>(row) * bw + degree) * in.channels + c] = 1.0f;
  }
  return in;
}

}  // namespace nurbs::gl_pingpong
