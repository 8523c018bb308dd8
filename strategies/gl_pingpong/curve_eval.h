// gl-pingpong's curve path: 000 §2.1-2.2, NURBS curve evaluation on OpenGL as the paper
// describes it, which is not the surface path (§3.1) run on one row:
//   CPU: span search, the width-2k+1 knot array and order-1 texture (§2.1, knot_array.h), and
//        the width-k control-point array, one row per parameter (§2.2);
//   GPU: k-1 order-raising ping-pong passes (basis_passes.h, shared with the surface path), one
//        multiply pass over the width-k array (multiply.frag), the per-row reduction
//        (reduce.frag: ceil(log2 k) pairwise passes, or one pass, see Reduction), and the divide
//        by w (divide.frag, shared with the surface path).
// The surface path instead accumulates the k_u x k_v products one pass each (accumulate.frag);
// harness/gbench measures the two side by side (curve/...).
// Float32, unpacked, positions only. Not a registry strategy: the project evaluates surfaces and
// meets curves as trimming curves; this is the §2.2 evaluator a trim pass or a benchmark calls.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string_view>
#include <vector>

#include "reference/curve.h"
#include "strategies/strategy.h"

namespace nurbs::gl_pingpong {

// How §2.2's "reduced along the width direction to its per-row sum" is done (the paper does not
// say): pairwise = ceil(log2 k) ping-pong passes each summing pairs of texels (the GPU reduction
// of the paper's time, chosen by default); single_pass = one pass summing the k texels of a row.
enum class Reduction { pairwise, single_pass };
std::string_view to_string(Reduction reduction);

// Passes of the last evaluate(), counted from the draws it issued (gl::DrawCounts), summed over
// the chunks of a parameter list longer than a texture.
struct CurvePasses {
  std::uint64_t basis = 0, multiply = 0, reduction = 0, divide = 0;
  std::uint64_t total() const { return basis + multiply + reduction + divide; }
};

class CurveEvaluator {
 public:
  // Options (StrategyOptions.extra): "gl" = osmesa | egl (default egl); "tile" = most parameters
  // per chunk (default GL_MAX_TEXTURE_SIZE rows). Throws std::runtime_error "unavailable: ..."
  // where no GL context can be made (and always in a build without OpenGL).
  explicit CurveEvaluator(const StrategyOptions& options,
                          Reduction reduction = Reduction::pairwise);
  ~CurveEvaluator();
  CurveEvaluator(const CurveEvaluator&) = delete;
  CurveEvaluator& operator=(const CurveEvaluator&) = delete;

  // Validates the curve (InputError naming field, index, value) and the parameters (finite),
  // builds and uploads the arrays; not part of evaluate()'s time.
  void prepare(const Curve& curve, const std::vector<double>& parameters);
  // The passes; returns when the device is done.
  void evaluate();
  // One point per parameter, in order.
  std::vector<Vec3<float>> read_back();

  CurvePasses passes() const;
  double device_seconds() const;  // GL_TIME_ELAPSED of the last evaluate()
  std::size_t bytes_uploaded() const;
  int tile() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace nurbs::gl_pingpong
