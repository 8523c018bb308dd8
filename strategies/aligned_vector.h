// Vectors whose storage starts on a 64-byte boundary (a cache line, and what AVX-512 loads want).
// Per-thread scratch must be in them: two small ordinary vectors allocated one after the other can
// share a cache line, and two threads writing it (false sharing) made cpu-tensor on many-4096 at
// 64^2 take 19 ms instead of 7-8 in some processes and not others, as the heap happened to lie.
#pragma once

#include <algorithm>
#include <cstddef>
#include <new>
#include <vector>

namespace nurbs {

inline constexpr std::size_t kCacheLineBytes = 64;

template <class T>
struct Aligned64 {
  using value_type = T;
  Aligned64() = default;
  template <class U>
  Aligned64(const Aligned64<U>&) {}
  // Rounded up to whole lines, so the last line is this vector's alone too.
  T* allocate(std::size_t n) {
    return static_cast<T*>(::operator new (rounded_bytes(n), std::align_val_t{kCacheLineBytes}));
  }
  void deallocate(T* p, std::size_t n) {
    ::operator delete (p, rounded_bytes(n), std::align_val_t{kCacheLineBytes});
  }
  template <class U>
  bool operator==(const Aligned64<U>&) const {
    return true;
  }

 private:
  static std::size_t rounded_bytes(std::size_t n) {
    const std::size_t bytes = std::max<std::size_t>(n, 1) * sizeof(T);
    return (bytes + kCacheLineBytes - 1) / kCacheLineBytes * kCacheLineBytes;
  }
};

template <class T>
using AlignedVector = std::vector<T, Aligned64<T>>;

}  // namespace nurbs
