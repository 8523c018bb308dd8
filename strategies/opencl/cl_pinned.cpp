#include "strategies/opencl/cl_pinned.h"

namespace nurbs::opencl {

void* PinnedHost::reserve(std::size_t bytes, const char* what) {
  if (mapped_ && capacity_ >= bytes) return mapped_;
  release();
  const std::size_t size = bytes == 0 ? 1 : bytes;
  buffer_ = ctx_->buffer(CL_MEM_ALLOC_HOST_PTR | CL_MEM_READ_WRITE, size, what);
  Batch batch;
  cl_int status = CL_SUCCESS;
  void* mapped = clEnqueueMapBuffer(ctx_->queue(), buffer_, CL_FALSE, CL_MAP_READ | CL_MAP_WRITE, 0,
                                    size, 0, nullptr, batch.next(), &status);
  check(status, "clEnqueueMapBuffer (pinned host memory)");
  batch.wait("clEnqueueMapBuffer (pinned host memory)");
  mapped_ = mapped;
  capacity_ = size;
  return mapped_;
}

void PinnedHost::release() {
  if (mapped_) clEnqueueUnmapMemObject(ctx_->queue(), buffer_, mapped_, 0, nullptr, nullptr);
  if (buffer_) clReleaseMemObject(buffer_);
  buffer_ = nullptr;
  mapped_ = nullptr;
  capacity_ = 0;
}

}  // namespace nurbs::opencl
