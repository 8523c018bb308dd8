// 000 §2.1: after each ping-pong pass the basis texture holds the basis functions of that order.
// Every intermediate order (not just the last) is compared with nurbs::basis_functions (A2.2)
// evaluated on the CPU in float at the same float parameter and span, on OSMesa and EGL, packed
// and unpacked, for degrees 1..9 and 15, on knot vectors with repeated interior knots (the 0/0
// terms the paper sets to zero explicitly).
#include "strategies/gl_pingpong/basis_passes.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/sampling.h"
#include "strategies/gl_context/gl_context.h"
#include "tests/reference/test_support.h"

namespace nurbs {
namespace {

struct Case {
  gl::Platform platform;
  bool packed;
};

void PrintTo(const Case& c, std::ostream* os) {
  *os << gl::to_string(c.platform) << (c.packed ? "/packed" : "/unpacked");
}

class BasisPasses : public ::testing::TestWithParam<Case> {};

TEST_P(BasisPasses, EveryIntermediateOrderEqualsTheReferenceBasis) {
  const Case c = GetParam();
  const Availability a = gl::Context::probe(c.platform);
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  auto context = gl::Context::create(c.platform);
  gl_pingpong::Programs programs(*context, c.packed);
  for (int degree : {1, 2, 3, 4, 5, 6, 7, 8, 9, 15}) {
    const int count = 3 * degree + 4;
    const std::vector<double> knots_d = test::knots_with_crease(degree, count);
    ASSERT_EQ(knots_d.size(), static_cast<std::size_t>(count + degree + 1));
    const std::vector<float> knots(knots_d.begin(), knots_d.end());
    // Every knot, the ends and 61 parameters in between (61: a packed last row is partial).
    std::vector<double> params = grid_parameters(0.0, 1.0, 61);
    for (int i = degree; i <= count; ++i) params.push_back(knots_d[static_cast<std::size_t>(i)]);
    const gl_pingpong::ChunkInputs in =
        gl_pingpong::make_chunk_inputs(params, 0, params.size(), degree, count, knots, c.packed);
    gl_pingpong::BasisChunk chunk(*context, in);
    const int order = degree + 1, width = in.basis_width();
    for (int passes = 1; passes <= degree; ++passes) {
      chunk.raise(programs.basis, passes);
      const std::vector<float> texels = chunk.read_result();
      ASSERT_EQ(texels.size(), static_cast<std::size_t>(width) * in.rows * 4);
      const int d = passes;  // this order's degree
      for (int q = 0; q < in.count; ++q) {
        const int row = c.packed ? q / 4 : q, channel = c.packed ? q % 4 : 0;
        float expected[kMaxOrder] = {};
        basis_functions(in.spans[q], in.parameters[q], d, knots.data(), expected);
        for (int j = 0; j < width; ++j) {
          const float got = texels[(static_cast<std::size_t>(row) * width + j) * 4 + channel];
          // Column j holds N_{s-p+j}: the reference's N_{s-d..s} sit in columns p-d..p, every
          // other column (and the pad column k) is exactly zero.
          const int r = j - (degree - d);
          const float want = (r >= 0 && r <= d && j < order) ? expected[r] : 0.0f;
          ASSERT_TRUE(std::abs(got - want) <= 4 * FLT_EPSILON)
              << "degree " << degree << ", order " << d + 1 << " (pass " << passes
              << "), u=" << in.parameters[q] << " span " << in.spans[q] << ", column " << j
              << ": got " << got << ", reference " << want;
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Platforms, BasisPasses,
                         ::testing::Values(Case{gl::Platform::osmesa, false},
                                           Case{gl::Platform::osmesa, true},
                                           Case{gl::Platform::egl, false},
                                           Case{gl::Platform::egl, true}),
                         [](const auto& info) {
                           return std::string(gl::to_string(info.param.platform)) +
                                  (info.param.packed ? "_packed" : "_unpacked");
                         });

}  // namespace
}  // namespace nurbs
