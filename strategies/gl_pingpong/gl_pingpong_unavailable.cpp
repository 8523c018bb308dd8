// gl-pingpong when the build has no OpenGL (no OSMesa/EGL development packages, or
// NURBSBENCH_CPU_ONLY): still registered, so `list` and results say why it did not run.
#include <fmt/format.h>

#include "strategies/gl_pingpong/curve_eval.h"
#include "strategies/gl_pingpong/gl_pingpong.h"
#include "strategies/gl_pingpong/lod_renderer.h"

namespace nurbs {

std::unique_ptr<gl_pingpong::LodRenderer> gl_pingpong::make_lod_renderer(const Scene&, int, int,
                                                                         const StrategyOptions&) {
  throw std::runtime_error(fmt::format("unavailable: {}", NURBSBENCH_GL_MISSING));
}

StrategyEntry gl_pingpong_entry() {
  return unavailable_entry(gl_pingpong_descriptor(false), NURBSBENCH_GL_MISSING);
}
StrategyEntry gl_pingpong_packed_entry() {
  return unavailable_entry(gl_pingpong_descriptor(true), NURBSBENCH_GL_MISSING);
}

// The curve path (curve_eval.h): never constructed here, so the other members are unreachable.
namespace gl_pingpong {

struct CurveEvaluator::Impl {};

std::string_view to_string(Reduction reduction) {
  return reduction == Reduction::pairwise ? "pairwise" : "single-pass";
}

CurveEvaluator::CurveEvaluator(const StrategyOptions&, Reduction) {
  throw std::runtime_error(std::string("unavailable: ") + NURBSBENCH_GL_MISSING);
}
CurveEvaluator::~CurveEvaluator() = default;
void CurveEvaluator::prepare(const Curve&, const std::vector<double>&) {}
void CurveEvaluator::evaluate() {}
std::vector<Vec3<float>> CurveEvaluator::read_back() {
  return {};
}
CurvePasses CurveEvaluator::passes() const {
  return {};
}
double CurveEvaluator::device_seconds() const {
  return 0;
}
std::size_t CurveEvaluator::bytes_uploaded() const {
  return 0;
}
int CurveEvaluator::tile() const {
  return 0;
}

}  // namespace gl_pingpong
}  // namespace nurbs
