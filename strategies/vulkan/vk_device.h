// The Vulkan plumbing shared by every Vulkan strategy (docs/design.md §GPU plumbing is shared):
// instance (the Khronos validation layer on in debug builds when it is installed), physical-device
// choice (a discrete, then an integrated GPU when present, else the first device -- lavapipe here;
// StrategyOptions.extra["device"] = N picks the N-th of vkEnumeratePhysicalDevices), the features a
// strategy requires checked up front ("<feature> not supported by <device>"), buffers (host-visible
// memory mapped directly, device-local memory through a staging buffer), one-shot command
// submission, shader modules from embedded SPIR-V, timestamp and pipeline-statistics queries, and
// the device record (lavapipe is kind "cpu": a lavapipe figure is a CPU figure).
#pragma once

#include <vulkan/vulkan.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "strategies/strategy.h"

namespace nurbs::vulkan {

// The device features a strategy needs; each missing one is named in the unavailable reason.
struct Requirements {
  bool tessellation_shader = false;
  bool vertex_pipeline_stores = false;  // storage-buffer writes from vertex/tessellation stages
  bool pipeline_statistics = false;
  bool geometry_shader = false;
  // Not required: shaderFloat64 is enabled where the device has it (Device::float64()), so a
  // strategy can offer f64 there and refuse it with the reason elsewhere.
  bool float64_when_present = false;
};

// Throws std::runtime_error naming the call and the VkResult.
void check(VkResult result, const char* what);

// "no Vulkan loader/driver", "no Vulkan device", or "<feature> not supported by <device>" when
// the device a run without --device would pick lacks a required feature.
Availability probe(const Requirements& requirements);

// Device index meaning "no --device given": a discrete GPU, then an integrated one, else device 0.
inline constexpr int kPreferGpu = -1;

// Reads StrategyOptions.extra["device"] (default kPreferGpu); throws on a non-number.
int device_option(const StrategyOptions& options);

// Thrown when the chosen device lacks a required feature (a result "unavailable", not a crash).
class MissingFeature : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Every physical device the loader offers, each record marked with details "index" (for
// --device) and "chosen" (the one used without --device); the first also carries
// "loaded_libraries", the shared libraries loaded while the instance lived (the ICDs among them).
// Throws std::runtime_error when there is no loader or driver.
std::vector<DeviceInfo> list_devices();

class Device;

// A buffer and its memory; mapped for its whole life when host-visible.
class Buffer {
 public:
  Buffer() = default;
  // usage 0: a staging buffer (host-visible memory first). Throws RefusedError past
  // maxStorageBufferRange (storage buffers) or when the device is out of memory.
  Buffer(const Device& device, VkDeviceSize bytes, VkBufferUsageFlags usage, const char* what);
  ~Buffer() { reset(); }
  Buffer(Buffer&& other) noexcept { *this = std::move(other); }
  Buffer& operator=(Buffer&& other) noexcept;
  Buffer(const Buffer&) = delete;
  Buffer& operator=(const Buffer&) = delete;

  VkBuffer handle() const { return buffer_; }
  VkDeviceSize size() const { return size_; }
  // The host's view of host-visible memory, mapped for the buffer's life; nullptr otherwise.
  void* mapped() const { return mapped_; }
  // Host copies; through the device's staging buffer (Device::staging) when the memory is not
  // host-visible, or (reads) host-visible but uncached.
  void write(const void* data, VkDeviceSize bytes, VkDeviceSize offset = 0);
  void read(void* data, VkDeviceSize bytes, VkDeviceSize offset = 0) const;
  // The bytes [offset, offset + bytes) where the host can read them: the mapping itself when it is
  // host-cached (lavapipe), else the device's staging buffer after one vkCmdCopyBuffer into it.
  // Valid until the device's next staged transfer. A strategy scatters its results from here
  // straight into the caller's arrays: one copy of each byte on the host.
  const void* host_view(VkDeviceSize bytes, VkDeviceSize offset = 0) const;

 private:
  void reset();
  const Device* device_ = nullptr;
  VkBuffer buffer_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkDeviceSize size_ = 0;
  void* mapped_ = nullptr;
  bool host_cached_ = false;
};

// A 2D image with its memory and view (device-local), e.g. an offscreen render target.
class Image {
 public:
  Image(const Device& device, VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
        std::uint32_t width, std::uint32_t height);
  ~Image();
  Image(const Image&) = delete;
  Image& operator=(const Image&) = delete;
  VkImage handle() const { return image_; }
  VkImageView view() const { return view_; }

 private:
  void release();
  const Device& device_;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
};

class Device {
 public:
  // `device_index` = kPreferGpu or an index into vkEnumeratePhysicalDevices; throws
  // std::runtime_error when out of range, MissingFeature when a requirement is not met.
  Device(int device_index, const Requirements& requirements);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  DeviceInfo record() const;
  VkDevice handle() const { return device_; }
  VkPhysicalDevice physical() const { return physical_; }
  VkQueue queue() const { return queue_; }
  const VkPhysicalDeviceLimits& limits() const { return properties_.limits; }
  bool validation_enabled() const { return validation_; }
  std::uint32_t timestamp_valid_bits() const { return timestamp_bits_; }
  // shaderFloat64 enabled (asked by Requirements::float64_when_present and supported).
  bool float64() const { return float64_; }

  // Records `commands` into the device's command buffer (reused), submits it and waits for it,
  // at most device_wait_limit_s() (DeviceTimeout).
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& commands) const;
  VkShaderModule shader_module(std::string_view spirv) const;
  // Index of a memory type allowed by `type_bits` with `wanted` properties; -1 when none.
  int memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags wanted) const;
  // The device's staging buffer, host-visible and host-cached where the device has such memory,
  // holding at least `bytes`: made on the first staged transfer, grown (never shrunk) and reused
  // by every later one. A staging buffer allocated per transfer paid an allocation and the page
  // faults of fresh memory on every call: Vulkan read-back ran at 0.5 GB/s on an H200 that way.
  Buffer& staging(VkDeviceSize bytes) const;
  // Bytes Buffer::write has sent to this device so far: what a strategy's prepare() uploads
  // (UploadCount), for the upload-of-link fraction.
  std::uint64_t bytes_written() const { return bytes_written_; }
  void count_written(VkDeviceSize bytes) const { bytes_written_ += bytes; }

 private:
  void destroy();
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties_{};
  VkPhysicalDeviceMemoryProperties memory_{};
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::uint32_t queue_family_ = 0, timestamp_bits_ = 0;
  VkCommandPool pool_ = VK_NULL_HANDLE;
  bool validation_ = false;
  bool float64_ = false;
  mutable std::optional<Buffer> staging_;
  mutable std::uint64_t bytes_written_ = 0;
  // submit_and_wait's, reused by every submission (null after one that timed out).
  mutable VkCommandBuffer command_buffer_ = VK_NULL_HANDLE;
  mutable VkFence fence_ = VK_NULL_HANDLE;
};

// The bytes a prepare() sends to the device, recorded when it ends (however it ends) as the detail
// "bytes_uploaded" of the strategy's device record: the harness holds the upload phase's bandwidth
// against the API's link row with it.
class UploadCount {
 public:
  UploadCount(const Device& device, DeviceInfo& record)
      : device_(device), record_(record), start_(device.bytes_written()) {}
  ~UploadCount() {
    record_.details["bytes_uploaded"] = std::to_string(device_.bytes_written() - start_);
  }
  UploadCount(const UploadCount&) = delete;
  UploadCount& operator=(const UploadCount&) = delete;

 private:
  const Device& device_;
  DeviceInfo& record_;
  std::uint64_t start_;
};

// One descriptor set of storage buffers (binding k visible to stages[k]), with its layout and
// pool: what every pipeline here binds. Created once per strategy; write() points the bindings at
// buffers (again after each prepare()).
class StorageSet {
 public:
  StorageSet(const Device& device, const std::vector<VkShaderStageFlags>& stages);
  ~StorageSet();
  StorageSet(const StorageSet&) = delete;
  StorageSet& operator=(const StorageSet&) = delete;

  const VkDescriptorSetLayout& layout() const { return layout_; }
  const VkDescriptorSet& handle() const { return set_; }
  // buffers[k] to binding k; as many buffers as bindings.
  void write(const std::vector<const Buffer*>& buffers) const;

 private:
  const Device& device_;
  VkDescriptorSetLayout layout_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
};

// A compute pipeline on one StorageSet's layout with `push_bytes` of push constants (compute
// stage): the pipeline layout and the pipeline, created once. `specialization[k]` is the value of
// the shader's 32-bit specialization constant k (constant_id = k): work-group sizes and
// shared-memory tiles chosen from the device's limits at run time.
class ComputePipeline {
 public:
  ComputePipeline(const Device& device, const StorageSet& set, std::uint32_t push_bytes,
                  std::string_view spirv, const char* what,
                  const std::vector<std::uint32_t>& specialization = {});
  ~ComputePipeline();
  ComputePipeline(const ComputePipeline&) = delete;
  ComputePipeline& operator=(const ComputePipeline&) = delete;
  VkPipelineLayout layout() const { return layout_; }
  // Binds the pipeline and `set` (the one it was made for) to `cb`.
  void bind(VkCommandBuffer cb, const StorageSet& set) const;

 private:
  const Device& device_;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

// A global memory barrier from (src_stage, src_access) to (dst_stage, dst_access).
void memory_barrier(VkCommandBuffer cb, VkPipelineStageFlags src_stage, VkAccessFlags src_access,
                    VkPipelineStageFlags dst_stage, VkAccessFlags dst_access);

// Two timestamps around the measured work, and optionally the pipeline statistics of it.
class QueryPools {
 public:
  QueryPools(const Device& device, VkQueryPipelineStatisticFlags statistics);
  ~QueryPools();
  QueryPools(const QueryPools&) = delete;
  QueryPools& operator=(const QueryPools&) = delete;

  void reset(VkCommandBuffer cb) const;  // before begin()
  void begin(VkCommandBuffer cb) const;  // timestamp 0 (+ statistics query begins)
  void end(VkCommandBuffer cb) const;    // statistics query ends + timestamp 1
  // Seconds between the two timestamps; empty where the queue has no timestamps.
  std::optional<double> elapsed_s() const;
  // One value per bit of `statistics`, in bit order (Vulkan's order of results).
  std::vector<std::uint64_t> statistics() const;

 private:
  const Device& device_;
  VkQueryPool timestamps_ = VK_NULL_HANDLE, statistics_ = VK_NULL_HANDLE;
  int statistic_count_ = 0;
  double period_ns_ = 1;
  std::uint32_t valid_bits_ = 0;
};

}  // namespace nurbs::vulkan
