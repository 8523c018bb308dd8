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
// Throws DeviceTimeout naming `what` on expiry, std::runtime_error when the command failed.
void wait(cl_event event, const char* what);

// Seconds between CL_PROFILING_COMMAND_START and _END of a finished event.
double event_seconds(cl_event event);

// `bytes` between the host and `mem` (offset 0), enqueued non-blocking and waited for with wait():
// a blocking transfer has no bound. Return the transfer's seconds (0 when `bytes` is 0).
double write(const Context& ctx, cl_mem mem, const void* host, std::size_t bytes, const char* what);
double read(const Context& ctx, cl_mem mem, void* host, std::size_t bytes, const char* what);

// A read-only buffer holding `data`; adds the transfer's seconds to `*seconds` when given.
template <typename V>
cl_mem upload(const Context& ctx, const std::vector<V>& data, const char* what,
              double* seconds = nullptr) {
  const std::size_t bytes = data.size() * sizeof(V);
  cl_mem mem = ctx.buffer(CL_MEM_READ_ONLY, bytes, what);
  const double s = write(ctx, mem, data.data(), bytes, what);
  if (seconds) *seconds += s;
  return mem;
}

// Reads StrategyOptions.extra["device"] (default kPreferGpu); throws on a non-number.
int device_option(const StrategyOptions& options);

}  // namespace nurbs::opencl
