#include "strategies/opencl/cl_device.h"

#include <chrono>
#include <stdexcept>
#include <thread>

#include "strategies/device_wait.h"
#include "strategies/gpu_devices.h"

namespace nurbs::opencl {
namespace {

std::vector<cl_platform_id> platforms() {
  cl_uint n = 0;
  // -1001 (CL_PLATFORM_NOT_FOUND_KHR) from the ICD loader means no platform is installed.
  if (clGetPlatformIDs(0, nullptr, &n) != CL_SUCCESS || n == 0) return {};
  std::vector<cl_platform_id> ids(n);
  if (clGetPlatformIDs(n, ids.data(), nullptr) != CL_SUCCESS) return {};
  return ids;
}

std::vector<cl_device_id> devices(cl_platform_id platform) {
  cl_uint n = 0;
  if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 0, nullptr, &n) != CL_SUCCESS || n == 0)
    return {};
  std::vector<cl_device_id> ids(n);
  if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, n, ids.data(), nullptr) != CL_SUCCESS) return {};
  return ids;
}

std::string device_string(cl_device_id d, cl_device_info what) {
  std::size_t size = 0;
  if (clGetDeviceInfo(d, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
  std::string s(size, '\0');
  clGetDeviceInfo(d, what, size, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::string platform_string(cl_platform_id p, cl_platform_info what) {
  std::size_t size = 0;
  if (clGetPlatformInfo(p, what, 0, nullptr, &size) != CL_SUCCESS || size == 0) return {};
  std::string s(size, '\0');
  clGetPlatformInfo(p, what, size, s.data(), nullptr);
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

template <typename V>
V device_value(cl_device_id d, cl_device_info what) {
  V v{};
  clGetDeviceInfo(d, what, sizeof v, &v, nullptr);
  return v;
}

}  // namespace

void check(cl_int status, const char* what) {
  if (status != CL_SUCCESS)
    throw std::runtime_error(std::string(what) + " failed: OpenCL error " + std::to_string(status));
}

Availability probe() {
  const auto ps = platforms();
  if (ps.empty()) return {false, "no OpenCL platform"};
  for (cl_platform_id p : ps)
    if (!devices(p).empty()) return {true, ""};
  return {false, "no OpenCL device"};
}

int device_option(const StrategyOptions& options) {
  const auto it = options.extra.find("device");
  if (it == options.extra.end() || it->second.empty()) return kPreferGpu;
  std::size_t used = 0;
  const int n = std::stoi(it->second, &used);
  if (used != it->second.size() || n < 0)
    throw std::runtime_error("--device expects a device number >= 0, got '" + it->second + "'");
  return n;
}

namespace {

// Without --device: the first GPU device if there is one (docs/design.md §GPU plumbing is shared:
// the same binary picks a real GPU when present), else the first device (PoCL's CPU device here).
// -1 when there is none.
int preferred_index(const std::vector<std::pair<cl_platform_id, cl_device_id>>& all) {
  int first = all.empty() ? -1 : 0;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (device_value<cl_device_type>(all[i].second, CL_DEVICE_TYPE) & CL_DEVICE_TYPE_GPU)
      return static_cast<int>(i);
  return first;
}

std::vector<std::pair<cl_platform_id, cl_device_id>> all_devices() {
  std::vector<std::pair<cl_platform_id, cl_device_id>> all;
  for (cl_platform_id p : platforms())
    for (cl_device_id d : devices(p)) all.emplace_back(p, d);
  return all;
}

DeviceInfo device_info(cl_platform_id platform, cl_device_id device) {
  const auto type = device_value<cl_device_type>(device, CL_DEVICE_TYPE);
  DeviceInfo info;
  info.name = device_string(device, CL_DEVICE_NAME);
  // PoCL's device is the host CPU: "cpu", so no result reads as a GPU measurement.
  info.kind = (type & CL_DEVICE_TYPE_GPU) ? "gpu" : (type & CL_DEVICE_TYPE_CPU) ? "cpu" : "other";
  info.details["platform"] = platform_string(platform, CL_PLATFORM_NAME);
  info.details["platform_version"] = platform_string(platform, CL_PLATFORM_VERSION);
  info.details["device_version"] = device_string(device, CL_DEVICE_VERSION);
  info.details["driver_version"] = device_string(device, CL_DRIVER_VERSION);
  info.details["compute_units"] =
      std::to_string(device_value<cl_uint>(device, CL_DEVICE_MAX_COMPUTE_UNITS));
  info.details["max_mem_alloc_size"] =
      std::to_string(device_value<cl_ulong>(device, CL_DEVICE_MAX_MEM_ALLOC_SIZE));
  info.details["max_work_group_size"] =
      std::to_string(device_value<std::size_t>(device, CL_DEVICE_MAX_WORK_GROUP_SIZE));
  info.details["local_mem_size"] =
      std::to_string(device_value<cl_ulong>(device, CL_DEVICE_LOCAL_MEM_SIZE));
  info.details["fp64"] =
      device_string(device, CL_DEVICE_EXTENSIONS).find("cl_khr_fp64") != std::string::npos ? "yes"
                                                                                           : "no";
  return info;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  const auto all = all_devices();
  if (all.empty())
    throw std::runtime_error(platforms().empty() ? "no OpenCL platform" : "no OpenCL device");
  const int chosen = preferred_index(all);
  std::vector<DeviceInfo> listed;
  for (std::size_t i = 0; i < all.size(); ++i) {
    DeviceInfo info = device_info(all[i].first, all[i].second);
    info.details["index"] = std::to_string(i);
    info.details["chosen"] = static_cast<int>(i) == chosen ? "yes" : "no";
    listed.push_back(std::move(info));
  }
  listed.front().details["loaded_libraries"] = loaded_libraries_text();
  return listed;
}

Context::Context(int device_index) {
  const auto all = all_devices();
  const int index = device_index == kPreferGpu ? preferred_index(all) : device_index;
  if (index < 0 || index >= static_cast<int>(all.size())) {
    if (all.empty()) throw std::runtime_error("no OpenCL platform");
    throw std::runtime_error("OpenCL device " + std::to_string(device_index) + " does not exist (" +
                             std::to_string(all.size()) + " found)");
  }
  platform_ = all[static_cast<std::size_t>(index)].first;
  device_ = all[static_cast<std::size_t>(index)].second;
  cl_int status = CL_SUCCESS;
  context_ = clCreateContext(nullptr, 1, &device_, nullptr, nullptr, &status);
  check(status, "clCreateContext");
  queue_ = clCreateCommandQueue(context_, device_, CL_QUEUE_PROFILING_ENABLE, &status);
  check(status, "clCreateCommandQueue");
  max_alloc_ =
      static_cast<std::size_t>(device_value<cl_ulong>(device_, CL_DEVICE_MAX_MEM_ALLOC_SIZE));
  max_work_group_ = device_value<std::size_t>(device_, CL_DEVICE_MAX_WORK_GROUP_SIZE);
}

Context::~Context() {
  if (queue_) clReleaseCommandQueue(queue_);
  if (context_) clReleaseContext(context_);
}

DeviceInfo Context::record() const {
  return device_info(platform_, device_);
}

bool Context::has_fp64() const {
  return device_string(device_, CL_DEVICE_EXTENSIONS).find("cl_khr_fp64") != std::string::npos;
}

cl_program Context::build(const std::string& source, const std::string& options) const {
  const char* text = source.c_str();
  const std::size_t length = source.size();
  cl_int status = CL_SUCCESS;
  cl_program program = clCreateProgramWithSource(context_, 1, &text, &length, &status);
  check(status, "clCreateProgramWithSource");
  if (clBuildProgram(program, 1, &device_, options.c_str(), nullptr, nullptr) != CL_SUCCESS) {
    std::size_t size = 0;
    clGetProgramBuildInfo(program, device_, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
    std::string log(size, '\0');
    clGetProgramBuildInfo(program, device_, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr);
    clReleaseProgram(program);
    throw std::runtime_error("OpenCL program build failed (options '" + options + "'):\n" + log);
  }
  return program;
}

cl_mem Context::buffer(cl_mem_flags flags, std::size_t bytes, const char* what) const {
  if (bytes > max_alloc_)
    throw RefusedError(std::string(what) + " needs " + std::to_string(bytes) +
                       " bytes, more than CL_DEVICE_MAX_MEM_ALLOC_SIZE (" +
                       std::to_string(max_alloc_) + ")");
  cl_int status = CL_SUCCESS;
  cl_mem mem = clCreateBuffer(context_, flags, bytes == 0 ? 1 : bytes, nullptr, &status);
  check(status, "clCreateBuffer");
  return mem;
}

void wait(cl_event event, const char* what) {
  cl_command_queue queue = nullptr;
  check(clGetEventInfo(event, CL_EVENT_COMMAND_QUEUE, sizeof queue, &queue, nullptr),
        "clGetEventInfo");
  check(clFlush(queue), "clFlush");
  // Polling, not a completion callback and a condition variable: NVIDIA's driver fires
  // clSetEventCallback's CL_COMPLETE callback late (measured on an H200: cl-stair at 1024²,
  // 19.97 ms of wall clock around a kernel of 1.87 ms on the device's clock), and that latency
  // landed in every timed phase. clWaitForEvents has no timeout, and the bound is a reliability
  // rule (docs/design.md §Reliability rules), so the status is polled: yielding for the first
  // kSpin (a GPU's short commands end within it, answered within microseconds), then sleeping
  // kSleep between polls (the sleep's latency, tens of microseconds plus the timer slack, is then
  // small against the command's own time, and a long kernel on PoCL does not lose a core to the
  // waiting thread).
  constexpr auto kSpin = std::chrono::microseconds(200);
  constexpr auto kSleep = std::chrono::microseconds(20);
  const auto start = std::chrono::steady_clock::now();
  const auto deadline = device_wait_deadline();
  for (;;) {
    cl_int status = CL_QUEUED;
    check(clGetEventInfo(event, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status, nullptr),
          "clGetEventInfo (CL_EVENT_COMMAND_EXECUTION_STATUS)");
    if (status == CL_COMPLETE) return;
    if (status < 0) check(status, what);  // the command failed: its error code
    const auto now = std::chrono::steady_clock::now();
    if (now >= deadline) throw device_timeout(what);
    if (now - start < kSpin)
      std::this_thread::yield();
    else
      std::this_thread::sleep_for(kSleep);
  }
}

double event_seconds(cl_event event) {
  cl_ulong start = 0, end = 0;
  check(clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_START, sizeof start, &start, nullptr),
        "clGetEventProfilingInfo");
  check(clGetEventProfilingInfo(event, CL_PROFILING_COMMAND_END, sizeof end, &end, nullptr),
        "clGetEventProfilingInfo");
  return static_cast<double>(end - start) * 1e-9;
}

void Batch::release() {
  for (cl_event e : events_)
    if (e) clReleaseEvent(e);
  events_.clear();
}

Batch::~Batch() {
  if (!failed_ && !events_.empty()) {
    try {
      wait("commands pending at an error");
    } catch (const std::exception&) {
      // The error being unwound is the one to report.
    }
  }
  release();
}

double Batch::wait(const char* what) {
  // An enqueue that failed left its slot empty (and threw): only issued commands are waited for.
  while (!events_.empty() && !events_.back()) events_.pop_back();
  if (events_.empty()) return 0;
  // In-order queue: the last command's completion means every earlier one has ended; each one's
  // status still says whether it failed.
  failed_ = true;
  opencl::wait(events_.back(), what);
  double seconds = 0;
  for (cl_event e : events_) {
    if (!e) continue;
    cl_int status = CL_COMPLETE;
    check(clGetEventInfo(e, CL_EVENT_COMMAND_EXECUTION_STATUS, sizeof status, &status, nullptr),
          "clGetEventInfo (CL_EVENT_COMMAND_EXECUTION_STATUS)");
    if (status != CL_COMPLETE) check(status < 0 ? status : CL_INVALID_EVENT, what);
    seconds += event_seconds(e);
  }
  failed_ = false;
  release();
  return seconds;
}

void enqueue_write(Batch& batch, const Context& ctx, cl_mem mem, std::size_t offset,
                   const void* host, std::size_t bytes, const char* what) {
  if (bytes == 0) return;
  check(clEnqueueWriteBuffer(ctx.queue(), mem, CL_FALSE, offset, bytes, host, 0, nullptr,
                             batch.next()),
        what);
  batch.add_bytes(bytes);
}

void enqueue_read(Batch& batch, const Context& ctx, cl_mem mem, std::size_t offset, void* host,
                  std::size_t bytes, const char* what) {
  if (bytes == 0) return;
  check(clEnqueueReadBuffer(ctx.queue(), mem, CL_FALSE, offset, bytes, host, 0, nullptr,
                            batch.next()),
        what);
  batch.add_bytes(bytes);
}

double write(const Context& ctx, cl_mem mem, const void* host, std::size_t bytes,
             const char* what) {
  Batch batch;
  enqueue_write(batch, ctx, mem, 0, host, bytes, what);
  return batch.wait(what);
}

double read(const Context& ctx, cl_mem mem, void* host, std::size_t bytes, const char* what) {
  Batch batch;
  enqueue_read(batch, ctx, mem, 0, host, bytes, what);
  return batch.wait(what);
}

void ensure_buffer(const Context& ctx, cl_mem* mem, std::size_t* capacity, cl_mem_flags flags,
                   std::size_t bytes, const char* what) {
  if (*mem && *capacity >= bytes) return;
  cl_mem grown = ctx.buffer(flags, bytes, what);
  if (*mem) clReleaseMemObject(*mem);
  *mem = grown;
  *capacity = bytes;
}

}  // namespace nurbs::opencl
