// How output rows reach a result far larger than the caches.
// stream_copy: a finished row copied from a cache-resident staging buffer with non-temporal
// (streaming) stores: they write whole lines through the write-combining buffers without first
// reading them (no read-for-ownership), so the output stream costs its own bytes rather than
// twice them, and the caches keep the tables and the net (cpu-tensor's stores=streaming).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace nurbs::tensor {

#if defined(__SSE2__)
inline void stream16(float* dst, const float* src) {
  _mm_stream_ps(dst, _mm_loadu_ps(src));
}
inline void stream16(double* dst, const double* src) {
  _mm_stream_pd(dst, _mm_loadu_pd(src));
}
#endif

// 16-byte streaming stores: the write-combining buffers gather them into full lines, so wider
// ones add nothing to the bandwidth and this needs no per-instruction-set clone. The head and
// tail outside 16-byte alignment use ordinary stores.
template <typename T>
void stream_copy(T* dst, const T* src, std::size_t n) {
#if defined(__SSE2__)
  constexpr std::size_t lanes = 16 / sizeof(T);
  std::size_t i = 0;
  for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + i) & 15) != 0; ++i) dst[i] = src[i];
  for (; i + lanes <= n; i += lanes) stream16(dst + i, src + i);
  for (; i < n; ++i) dst[i] = src[i];
#else
  std::copy(src, src + n, dst);
#endif
}

// Orders this thread's streaming stores before whatever follows (the end of the parallel region
// that hands the results to another thread): they are weakly ordered.
inline void stream_fence() {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

}  // namespace nurbs::tensor
