// The C++ builds of the single-source stair basis (strategies/stair_basis/stair_basis.h, 003
// §3.2): float as the devices run it, double, and long double for the tests. cl-stair compiles
// the same file as OpenCL C and vk-ksquad as GLSL; vk-ksquad uploads StairConstants<float> as
// computed here.
#pragma once

#include "reference/nurbs_math.h"

namespace nurbs {

namespace stair_source {
#define SB_REAL float
#include "strategies/stair_basis/stair_basis.h"
#undef SB_REAL
#define SB_REAL double
#include "strategies/stair_basis/stair_basis.h"
#undef SB_REAL
#define SB_REAL long double
#include "strategies/stair_basis/stair_basis.h"
#undef SB_REAL
}  // namespace stair_source

inline constexpr int kStairMaxDegree = SB_MAX_DEG;
inline constexpr int kStairConstantReals = SB_CONSTANT_REALS;
static_assert(kStairMaxDegree == kMaxDegree, "the stair basis covers every valid degree");

// The constants of one direction of one span, in the packed layout of stair_basis.h.
template <typename T>
struct StairConstants {
  T values[kStairConstantReals];
};

// `knots` is the whole knot vector, `span` = i.
template <typename T>
void stair_constants(int span, int degree, const T* knots, StairConstants<T>& c) {
  stair_source::stair_constants(span, degree, knots, c.values);
}

// basis[j] = N_{i-p+j,p}(u), j = 0..p; `knot_degree` (default: `degree`): see stair_basis.h.
template <typename T>
void stair_basis(const StairConstants<T>& c, int degree, T u, T* basis, int knot_degree = -1) {
  stair_source::stair_basis(c.values, degree, u, basis, knot_degree < 0 ? degree : knot_degree);
}

// derivative[j] = d/du N_{i-p+j,p}(u), j = 0..p.
template <typename T>
void stair_derivative(const StairConstants<T>& c, int degree, T u, T* derivative) {
  stair_source::stair_derivative(c.values, degree, u, derivative);
}

}  // namespace nurbs
