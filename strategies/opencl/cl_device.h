// The OpenCL plumbing shared by every OpenCL strategy (docs/design.md §GPU plumbing is shared):
// platform/device choice (StrategyOptions.extra["device"] = N, devices numbered across all
// platforms in clGetPlatformIDs/clGetDeviceIDs order), the device record, program build with the
// build log in the error, profiling events, and buffers checked against
// CL_DEVICE_MAX_MEM_ALLOC_SIZE (refused, never truncated).
#pragma once

#define CL_TARGET_OPENCL_VERSION 120
#include <CL/cl.h>

#include <cstddef>
#include <string>
#include <vector>

#include "strategies/strategy.h"

namespace nurbs::opencl {

// "no OpenCL platform" / "no OpenCL device" when there is nothing to run on.
Availability probe();

// Throws std::runtime_error naming the call and the error code.
void check(cl_int status, const char* what);

// Device index meaning "no --device given": the first GPU device, else the first device.
inline constexpr int kPreferGpu = -1;

// Every device over all platforms, in --device order, each record marked with details "index"
// and "chosen" (the one used without --device); the first also carries "loaded_libraries" (the
// ICDs among them). Throws std::runtime_error when there is no platform or device.
std::vector<DeviceInfo> list_devices();

class Context {
 public:
  // `device_index` counts devices over all platforms; throws when out of range.
  explicit Context(int device_index);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  DeviceInfo record() const;  // kind "cpu" for CPU devices (PoCL), "gpu" for GPUs
  bool has_fp64() const;
  std::size_t max_alloc() const { return max_alloc_; }
  std::size_t max_work_group() const { return max_work_group_; }
  cl_context context() const { return context_; }
  cl_command_queue queue() const { return queue_; }
  cl_device_id device() const { return device_; }

  // Builds `source`; on failure throws std::runtime_error carrying the build log.
  cl_program build(const std::string& source, const std::string& options) const;
  // A buffer of `bytes`; throws RefusedError when it exceeds CL_DEVICE_MAX_MEM_ALLOC_SIZE.
  cl_mem buffer(cl_mem_flags flags, std::size_t bytes, const char* what) const;

 private:
  cl_platform_id platform_ = nullptr;
  cl_device_id device_ = nullptr;
  cl_context context_ = nullptr;
  cl_command_queue queue_ = nullptr;
  std::size_t max_alloc_ = 0, max_work_group_ = 1;
};

// Flushes the event's queue and waits for the event at most device_wait_limit_s()
// (strategies/device_wait.h): clWaitForEvents, clFinish and blocking transfers have no bound.
// Polls the event's status (cl_device.cpp says why not a completion callback). Throws
// DeviceTimeout naming `what` on expiry, std::runtime_error when the command failed.
void wait(cl_event event, const char* what);

// Seconds between CL_PROFILING_COMMAND_START and _END of a finished event.
double event_seconds(cl_event event);

// Commands enqueued back to back on the context's (in-order) queue and waited for once: a phase's
// transfers (or launches) pay one completion wait, not one per buffer, and their profiled seconds
// are summed. The host memory a command reads or writes must stay valid until wait() returns: a
// batch destroyed unwaited (an exception between enqueue and wait) waits for its commands,
// bounded and quietly, unless its own wait() failed (a device that timed out is not waited for
// twice).
class Batch {
 public:
  Batch() = default;
  ~Batch();
  Batch(const Batch&) = delete;
  Batch& operator=(const Batch&) = delete;

  // Where the next enqueue call stores its event.
  cl_event* next() {
    events_.push_back(nullptr);
    return &events_.back();
  }
  // Waits for the last command (wait()), checks that every command completed, returns the sum of
  // their profiled seconds (0 for an empty batch) and empties the batch.
  double wait(const char* what);
  // Bytes moved by the batch's transfers (write/read below), for the record.
  std::size_t bytes() const { return bytes_; }
  void add_bytes(std::size_t bytes) { bytes_ += bytes; }

 private:
  void release();
  std::vector<cl_event> events_;
  std::size_t bytes_ = 0;
  bool failed_ = false;
};

// `bytes` between the host and `mem` (at `offset`), enqueued non-blocking into `batch` (nothing
// for 0 bytes): a blocking transfer has no bound.
void enqueue_write(Batch& batch, const Context& ctx, cl_mem mem, std::size_t offset,
                   const void* host, std::size_t bytes, const char* what);
void enqueue_read(Batch& batch, const Context& ctx, cl_mem mem, std::size_t offset, void* host,
                  std::size_t bytes, const char* what);

// One transfer, waited for: returns its seconds (0 when `bytes` is 0).
double write(const Context& ctx, cl_mem mem, const void* host, std::size_t bytes, const char* what);
double read(const Context& ctx, cl_mem mem, void* host, std::size_t bytes, const char* what);

// A read-only buffer holding `data`, its write enqueued into `batch` (`data` must outlive the
// batch's wait()).
template <typename V>
cl_mem upload(const Context& ctx, const std::vector<V>& data, const char* what, Batch& batch) {
  const std::size_t bytes = data.size() * sizeof(V);
  cl_mem mem = ctx.buffer(CL_MEM_READ_ONLY, bytes, what);
  enqueue_write(batch, ctx, mem, 0, data.data(), bytes, what);
  return mem;
}

// `mem` kept at `bytes` or more (grown, never shrunk, contents not kept): output buffers a
// strategy reuses across prepare() calls, so no call pays a fresh allocation's first touches.
// `*capacity` is the size `mem` has.
void ensure_buffer(const Context& ctx, cl_mem* mem, std::size_t* capacity, cl_mem_flags flags,
                   std::size_t bytes, const char* what);

// Reads StrategyOptions.extra["device"] (default kPreferGpu); throws on a non-number.
int device_option(const StrategyOptions& options);

}  // namespace nurbs::opencl
