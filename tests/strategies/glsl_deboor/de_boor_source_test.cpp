// The single-source de Boor (strategies/glsl_deboor/de_boor_source.h) through both of its builds
// on the same inputs: the C++ float build (strategies/glsl_deboor/de_boor.h) and the GLSL build as
// glsl-deboor compiles it (de_boor_defines: DEGREE, then the source), one fragment per case on
// llvmpipe, read back. Degrees 1..15; per degree, random non-decreasing knots around a non-empty
// span (repeated knots included), random homogeneous points, parameters across the span with
// both ends. Both builds are also held to the long double build, so two equally wrong builds
// fail too.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "reference/nurbs_math.h"
#include "strategies/gl_context/gl_context.h"
#include "strategies/gl_context/gl_program.h"
#include "strategies/glsl_deboor/de_boor.h"
#include "strategies/glsl_deboor/deboor_evaluator.h"

namespace nurbs::embedded {
extern const std::string_view gl_fullscreen_triangle_vert;
}  // namespace nurbs::embedded

namespace nurbs::glsl_deboor {
namespace {

// Row y of the input texture is case y: texels [0, 2p) knots (.r), [2p, 3p] the p+1 homogeneous
// points, 3p+1 the parameter (.r). Output texel (0, y) = db_de_boor of case y.
constexpr std::string_view kFragment = R"(#version 330 core
uniform sampler2D inputs;
out vec4 result;
void main() {
  int row = int(gl_FragCoord.y);
  float K[2 * DEGREE];
  for (int t = 0; t < 2 * DEGREE; ++t) K[t] = texelFetch(inputs, ivec2(t, row), 0).r;
  vec4 d[DEGREE + 1];
  for (int j = 0; j <= DEGREE; ++j) d[j] = texelFetch(inputs, ivec2(2 * DEGREE + j, row), 0);
  float u = texelFetch(inputs, ivec2(3 * DEGREE + 1, row), 0).r;
  result = db_de_boor(DEGREE, K, u, d);
}
)";

struct Case {
  std::vector<float> K;
  std::vector<Vec4<float>> d;
  float u = 0;
};

std::vector<Case> cases(int p, std::mt19937& rng) {
  std::uniform_real_distribution<float> step(0.0f, 1.0f), coordinate(-10.0f, 10.0f),
      weight(0.25f, 4.0f);
  std::bernoulli_distribution repeat(0.25);
  std::vector<Case> out;
  for (int k = 0; k < 8; ++k) {
    Case base;
    base.K.resize(2 * p);
    // K[p-1] < K[p] bound the span; the others may repeat their neighbour.
    base.K[p - 1] = step(rng);
    base.K[p] = base.K[p - 1] + 0.01f + step(rng);
    for (int t = p - 2; t >= 0; --t) base.K[t] = base.K[t + 1] - (repeat(rng) ? 0.0f : step(rng));
    for (int t = p + 1; t < 2 * p; ++t)
      base.K[t] = base.K[t - 1] + (repeat(rng) ? 0.0f : step(rng));
    for (int j = 0; j <= p; ++j) {
      const float w = weight(rng);
      base.d.push_back({coordinate(rng) * w, coordinate(rng) * w, coordinate(rng) * w, w});
    }
    for (int s = 0; s <= 8; ++s) {
      Case c = base;
      c.u = s == 8 ? base.K[p] : base.K[p - 1] + (base.K[p] - base.K[p - 1]) * float(s) / 8.0f;
      out.push_back(c);
    }
  }
  return out;
}

// Float32 ulps between two values, on the scale of the case's largest homogeneous coordinate
// (de Boor's convex combinations never leave the points' hull).
double ulps(float a, float b, float scale) {
  return std::fabs(double(a) - double(b)) / (double(std::nextafter(scale, 2 * scale)) - scale);
}

TEST(DeBoorSource, GlslBuildEqualsCppBuildBitForBit) {
  const Availability a = gl::Context::probe_any();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  std::unique_ptr<gl::Context> context = gl::Context::create(
      gl::Context::probe(gl::Platform::egl).available ? gl::Platform::egl : gl::Platform::osmesa);
  const gl::Functions& gl = context->gl();
  GLuint vertex_array = 0;
  gl.GenVertexArrays(1, &vertex_array);
  gl.BindVertexArray(vertex_array);
  std::mt19937 rng(2012);
  std::size_t compared = 0;
  for (int p = 1; p <= kMaxDegree; ++p) {
    SCOPED_TRACE("degree " + std::to_string(p));
    const std::vector<Case> all = cases(p, rng);
    const int width = 3 * p + 2, rows = static_cast<int>(all.size());
    std::vector<float> texels(static_cast<std::size_t>(width) * rows * 4, 0.0f);
    for (int y = 0; y < rows; ++y) {
      float* row = &texels[static_cast<std::size_t>(y) * width * 4];
      for (int t = 0; t < 2 * p; ++t) row[t * 4] = all[y].K[t];
      for (int j = 0; j <= p; ++j)
        for (int c = 0; c < 4; ++c) row[(2 * p + j) * 4 + c] = all[y].d[j][c];
      row[(3 * p + 1) * 4] = all[y].u;
    }
    gl::Texture inputs(*context, GL_RGBA32F, width, rows, false);
    inputs.upload(GL_RGBA, GL_FLOAT, texels.data(), sizeof(float) * 4);
    gl::Texture output(*context, GL_RGBA32F, 1, rows, true);
    gl::Program program(*context, embedded::gl_fullscreen_triangle_vert, kFragment,
                        de_boor_defines(p), "de_boor_source_test");
    gl.UseProgram(program.id());
    gl.Uniform1i(program.uniform("inputs"), 0);
    inputs.bind_to_unit(0);
    output.bind_target();
    context->draw_arrays(GL_TRIANGLES, 0, 3);
    std::vector<float> got(static_cast<std::size_t>(rows) * 4);
    gl.ReadBuffer(GL_COLOR_ATTACHMENT0);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    context->read_pixels(0, 0, 1, rows, GL_RGBA, GL_FLOAT, got.data());
    context->check("de_boor_source_test");
    for (int y = 0; y < rows; ++y) {
      const Case& c = all[y];
      std::vector<Vec4<float>> d = c.d;
      const Vec4<float> cpp = de_boor(p, c.K.data(), c.u, d.data());
      std::vector<long double> K(c.K.begin(), c.K.end());
      std::vector<Vec4<long double>> dl;
      float scale = 0;
      for (const Vec4<float>& q : c.d) {
        dl.push_back({q[0], q[1], q[2], q[3]});
        for (float x : q) scale = std::max(scale, std::fabs(x));
      }
      const Vec4<long double> exact =
          de_boor(p, K.data(), static_cast<long double>(c.u), dl.data());
      for (int k = 0; k < 4; ++k) {
        const float glsl = got[static_cast<std::size_t>(y) * 4 + k];
        ASSERT_EQ(std::bit_cast<std::uint32_t>(glsl), std::bit_cast<std::uint32_t>(cpp[k]))
            << "case " << y << " component " << k << ": GLSL " << glsl << ", C++ " << cpp[k];
        // Each of the p(p+1)/2 convex combinations rounds at most a few times.
        EXPECT_LE(ulps(cpp[k], static_cast<float>(exact[k]), scale), 4.0 * p * (p + 1))
            << "case " << y << " component " << k;
        ++compared;
      }
    }
    gl.UseProgram(0);
  }
  EXPECT_EQ(compared, std::size_t{4 * 72 * kMaxDegree});
  gl.DeleteVertexArrays(1, &vertex_array);
}

}  // namespace
}  // namespace nurbs::glsl_deboor
