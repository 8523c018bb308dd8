// Pinned host memory for transfers at the link's speed: a CL_MEM_ALLOC_HOST_PTR buffer mapped
// once, whose mapped pointer is then the host side of clEnqueueReadBuffer/WriteBuffer on other
// buffers (NVIDIA's OpenCL Best Practices Guide §3.1.1, "pinned memory"; the same idiom as the
// limit-link-opencl row, strategies/link_copy.h). A transfer between device memory and pageable
// memory goes through the driver's own bounce buffers in chunks; from page-locked memory it is
// one DMA.
//
// Mapped once and kept mapped, not mapped and unmapped per transfer: OpenCL 1.2 §5.4.2.1 only
// forbids commands on the *mapped buffer itself* while it is mapped; using the mapped region as
// the host pointer of a transfer on another buffer is an ordinary host pointer, and the region
// stays valid until clEnqueueUnmapMemObject. A map/unmap pair per transfer would add two commands
// and their waits to every read-back.
#pragma once

#include <cstddef>

#include "strategies/opencl/cl_device.h"

namespace nurbs::opencl {

class PinnedHost {
 public:
  // Nothing is allocated before the first reserve().
  explicit PinnedHost(const Context& ctx) : ctx_(&ctx) {}
  ~PinnedHost() { release(); }
  PinnedHost(const PinnedHost&) = delete;
  PinnedHost& operator=(const PinnedHost&) = delete;

  // At least `bytes` of mapped pinned memory, grown when smaller (contents not kept), kept
  // otherwise. Throws RefusedError over CL_DEVICE_MAX_MEM_ALLOC_SIZE, std::runtime_error,
  // DeviceTimeout (the map is waited for with wait()).
  void* reserve(std::size_t bytes, const char* what);
  void* data() const { return mapped_; }
  std::size_t capacity() const { return capacity_; }

 private:
  // Unmaps (enqueued, not waited for: the buffer is freed once the unmap has run) and releases.
  void release();
  const Context* ctx_;
  cl_mem buffer_ = nullptr;
  void* mapped_ = nullptr;
  std::size_t capacity_ = 0;
};

}  // namespace nurbs::opencl
