// Copies a finished output row from a cache-resident staging buffer to its place in a result far
// larger than the caches with non-temporal (streaming) stores: they write whole lines through the
// write-combining buffers without first reading them (no read-for-ownership), so the output
// stream costs its own bytes rather than twice them, and the caches keep the tables and the net.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace nurbs::tensor {

// 16-byte streaming stores: the write-combining buffers gather them into full lines, so wider
// ones add nothing to the bandwidth and this needs no per-instruction-set clone. The head and
// tail outside 16-byte alignment use ordinary stores.
inline void stream_copy(float* dst, const float* src, std::size_t n) {
#if defined(__SSE2__)
  std::size_t i = 0;
  for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + i) & 15) != 0; ++i) dst[i] = src[i];
  for (; i + 4 <= n; i += 4) _mm_stream_ps(dst + i, _mm_loadu_ps(src + i));
  for (; i < n; ++i) dst[i] = src[i];
#else
  std::copy(src, src + n, dst);
#endif
}

inline void stream_copy(double* dst, const double* src, std::size_t n) {
#if defined(__SSE2__)
  std::size_t i = 0;
  for (; i < n && (reinterpret_cast<std::uintptr_t>(dst + i) & 15) != 0; ++i) dst[i] = src[i];
  for (; i + 2 <= n; i += 2) _mm_stream_pd(dst + i, _mm_loadu_pd(src + i));
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
