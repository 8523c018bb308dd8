// Scalar types the NURBS math is instantiated with, and the few math functions it needs, so that
// the same templates serve float (what GPUs compute in), double, long double (the reference) and
// __float128 (the reference on request).
#pragma once

#include <cmath>
#include <limits>
#include <string_view>

#if defined(__SIZEOF_FLOAT128__) && !defined(__clang__)
#include <quadmath.h>
#define NURBSBENCH_HAS_FLOAT128 1
#else
#define NURBSBENCH_HAS_FLOAT128 0
#endif

namespace nurbs {

template <typename T>
inline T scalar_sqrt(T x) {
  return std::sqrt(x);
}
template <typename T>
inline T scalar_abs(T x) {
  return std::fabs(x);
}
template <typename T>
inline bool scalar_isfinite(T x) {
  return std::isfinite(x);
}
template <typename T>
constexpr T scalar_epsilon() {
  return std::numeric_limits<T>::epsilon();
}

#if NURBSBENCH_HAS_FLOAT128
using float128 = __float128;
template <>
inline float128 scalar_sqrt(float128 x) {
  return sqrtq(x);
}
template <>
inline float128 scalar_abs(float128 x) {
  return fabsq(x);
}
template <>
inline bool scalar_isfinite(float128 x) {
  return finiteq(x) != 0;
}
template <>
constexpr float128 scalar_epsilon<float128>() {
  return FLT128_EPSILON;
}
#endif

// The precision a strategy computes in (positions are returned in it too).
enum class Precision { f32, f64 };

inline std::string_view to_string(Precision p) {
  return p == Precision::f32 ? "f32" : "f64";
}

}  // namespace nurbs
