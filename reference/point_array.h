// n 3-vectors stored at the precision a strategy computed them in, so a float32 strategy's read
// back is a plain copy and a float64 one loses nothing; readers see doubles (float -> double is
// exact).
#pragma once

#include <array>
#include <cstddef>
#include <type_traits>
#include <vector>

#include "reference/scalar.h"

namespace nurbs {

class PointArray {
 public:
  PointArray() = default;
  PointArray(Precision precision, std::size_t count) : precision_(precision), count_(count) {
    if (precision == Precision::f32)
      f32_.resize(count * 3);
    else
      f64_.resize(count * 3);
  }

  // n points at `precision`, keeping the storage already held (no allocation, no page faults) when
  // it is large enough: the output buffers a strategy reuses across repetitions. Values of a kept
  // size are left as they were (callers overwrite every point); grown ones start at 0.
  void reset(Precision precision, std::size_t count) {
    precision_ = precision;
    count_ = count;
    if (precision == Precision::f32) {
      f32_.resize(count * 3);
      std::vector<double>().swap(f64_);
    } else {
      f64_.resize(count * 3);
      std::vector<float>().swap(f32_);
    }
  }

  Precision precision() const { return precision_; }
  std::size_t size() const { return count_; }
  bool empty() const { return count_ == 0; }
  float* f32() { return f32_.data(); }
  double* f64() { return f64_.data(); }
  const float* f32() const { return f32_.data(); }
  const double* f64() const { return f64_.data(); }
  // The storage as T (float for f32, double for f64): for code templated on the precision.
  template <typename T>
  T* data() {
    if constexpr (std::is_same_v<T, float>)
      return f32_.data();
    else
      return f64_.data();
  }
  template <typename T>
  const T* data() const {
    if constexpr (std::is_same_v<T, float>)
      return f32_.data();
    else
      return f64_.data();
  }

  // Writes point k from any scalar type, rounding to the stored precision.
  template <typename T>
  void set(std::size_t k, const std::array<T, 3>& p) {
    for (int c = 0; c < 3; ++c) {
      if (precision_ == Precision::f32)
        f32_[k * 3 + c] = static_cast<float>(p[c]);
      else
        f64_[k * 3 + c] = static_cast<double>(p[c]);
    }
  }

  std::array<double, 3> operator[](std::size_t k) const {
    if (precision_ == Precision::f32) return {f32_[k * 3], f32_[k * 3 + 1], f32_[k * 3 + 2]};
    return {f64_[k * 3], f64_[k * 3 + 1], f64_[k * 3 + 2]};
  }

 private:
  Precision precision_ = Precision::f64;
  std::size_t count_ = 0;
  std::vector<float> f32_;
  std::vector<double> f64_;
};

}  // namespace nurbs
