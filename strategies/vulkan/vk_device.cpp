#include "strategies/vulkan/vk_device.h"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

#include "strategies/device_wait.h"
#include "strategies/gpu_devices.h"

namespace nurbs::vulkan {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

[[maybe_unused]] bool layer_installed(const char* name) {
  std::uint32_t n = 0;
  if (vkEnumerateInstanceLayerProperties(&n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  return std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& l) {
    return std::strcmp(l.layerName, name) == 0;
  });
}

// Validation in debug builds only (it costs more than the work it checks); never required.
VkInstance create_instance(bool& validation) {
  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "nurbsbench";
  app.apiVersion = VK_API_VERSION_1_1;
  VkInstanceCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  info.pApplicationInfo = &app;
#ifndef NDEBUG
  validation = layer_installed(kValidationLayer);
#else
  validation = false;
#endif
  if (validation) {
    info.enabledLayerCount = 1;
    info.ppEnabledLayerNames = &kValidationLayer;
  }
  VkInstance instance = VK_NULL_HANDLE;
  const VkResult result = vkCreateInstance(&info, nullptr, &instance);
  if (result == VK_ERROR_INCOMPATIBLE_DRIVER) throw std::runtime_error("no Vulkan driver");
  check(result, "vkCreateInstance");
  return instance;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  std::uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(n);
  check(vkEnumeratePhysicalDevices(instance, &n, devices.data()), "vkEnumeratePhysicalDevices");
  return devices;
}

int preference(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
      return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
      return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
      return 2;
    default:
      return 3;
  }
}

// docs/design.md §GPU plumbing is shared: the same binary picks a real GPU when one is present.
VkPhysicalDevice choose(const std::vector<VkPhysicalDevice>& devices, int index) {
  if (devices.empty()) throw std::runtime_error("no Vulkan device");
  if (index == kPreferGpu) {
    VkPhysicalDevice best = devices.front();
    int best_rank = 99;
    for (VkPhysicalDevice d : devices) {
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(d, &p);
      if (preference(p.deviceType) < best_rank) {
        best = d;
        best_rank = preference(p.deviceType);
      }
    }
    return best;
  }
  if (index < 0 || index >= static_cast<int>(devices.size()))
    throw std::runtime_error(
        fmt::format("Vulkan device {} does not exist ({} found)", index, devices.size()));
  return devices[index];
}

// The first missing requirement, named as the Vulkan feature; empty when all are there.
std::string missing_feature(VkPhysicalDevice d, const Requirements& req) {
  VkPhysicalDeviceFeatures f;
  vkGetPhysicalDeviceFeatures(d, &f);
  VkPhysicalDeviceProperties p;
  vkGetPhysicalDeviceProperties(d, &p);
  const auto missing = [&](const char* feature) {
    return fmt::format("{} not supported by {}", feature, p.deviceName);
  };
  if (req.tessellation_shader && !f.tessellationShader) return missing("tessellationShader");
  if (req.vertex_pipeline_stores && !f.vertexPipelineStoresAndAtomics)
    return missing("vertexPipelineStoresAndAtomics");
  if (req.pipeline_statistics && !f.pipelineStatisticsQuery)
    return missing("pipelineStatisticsQuery");
  if (req.geometry_shader && !f.geometryShader) return missing("geometryShader");
  return {};
}

int graphics_compute_family(VkPhysicalDevice d) {
  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(d, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(d, &n, families.data());
  for (std::uint32_t k = 0; k < n; ++k)
    if ((families[k].queueFlags & VK_QUEUE_GRAPHICS_BIT) &&
        (families[k].queueFlags & VK_QUEUE_COMPUTE_BIT))
      return static_cast<int>(k);
  return -1;
}

std::string version_string(std::uint32_t v) {
  return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v),
                     VK_API_VERSION_PATCH(v));
}

bool has_device_extension(VkPhysicalDevice d, const char* name) {
  std::uint32_t n = 0;
  if (vkEnumerateDeviceExtensionProperties(d, nullptr, &n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> extensions(n);
  vkEnumerateDeviceExtensionProperties(d, nullptr, &n, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(), [&](const VkExtensionProperties& e) {
    return std::strcmp(e.extensionName, name) == 0;
  });
}

// The record of one physical device: what a result names as its device, with the limits that
// differ between a GPU and lavapipe (tessellation level, work groups, shared memory) and the
// driver's own name, so a record says which ICD produced it.
DeviceInfo device_info(VkPhysicalDevice physical, bool validation) {
  VkPhysicalDeviceProperties properties;
  vkGetPhysicalDeviceProperties(physical, &properties);
  DeviceInfo info;
  info.name = properties.deviceName;
  // lavapipe (VK_PHYSICAL_DEVICE_TYPE_CPU) and any other software device: "cpu".
  const auto type = properties.deviceType;
  info.kind = type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU ||
                      type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU ||
                      type == VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU
                  ? "gpu"
                  : "cpu";
  info.details["api"] = "Vulkan " + version_string(properties.apiVersion);
  info.details["driver_version"] = std::to_string(properties.driverVersion);
  info.details["vendor_id"] = fmt::format("{:#06x}", properties.vendorID);
  info.details["device_type"] = type == VK_PHYSICAL_DEVICE_TYPE_CPU              ? "cpu"
                                : type == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU   ? "discrete gpu"
                                : type == VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU ? "integrated gpu"
                                                                                 : "other";
  const VkPhysicalDeviceLimits& limits = properties.limits;
  info.details["max_tessellation_generation_level"] =
      std::to_string(limits.maxTessellationGenerationLevel);
  info.details["max_tessellation_patch_size"] = std::to_string(limits.maxTessellationPatchSize);
  info.details["max_compute_work_group_invocations"] =
      std::to_string(limits.maxComputeWorkGroupInvocations);
  info.details["max_compute_shared_memory_size"] =
      std::to_string(limits.maxComputeSharedMemorySize);
  info.details["timestamp_period_ns"] = fmt::format("{}", limits.timestampPeriod);
  // The driver's name (VK_KHR_driver_properties, core in 1.2): "NVIDIA", "llvmpipe"...
  if (has_device_extension(physical, "VK_KHR_driver_properties")) {
    VkPhysicalDeviceDriverProperties driver{};
    driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
    VkPhysicalDeviceProperties2 properties2{};
    properties2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    properties2.pNext = &driver;
    vkGetPhysicalDeviceProperties2(physical, &properties2);
    info.details["driver"] = fmt::format("{} {}", driver.driverName, driver.driverInfo);
  }
  info.details["validation"] = validation ? "on" : "off";
  return info;
}

}  // namespace

void check(VkResult result, const char* what) {
  if (result != VK_SUCCESS)
    throw std::runtime_error(fmt::format("{} failed: VkResult {}", what, static_cast<int>(result)));
}

Availability probe(const Requirements& requirements) {
  try {
    bool validation = false;
    VkInstance instance = create_instance(validation);
    std::string reason;
    try {
      reason = missing_feature(choose(physical_devices(instance), kPreferGpu), requirements);
    } catch (const std::exception& e) {
      reason = e.what();
    }
    vkDestroyInstance(instance, nullptr);
    return {reason.empty(), reason};
  } catch (const std::exception& e) {
    return {false, e.what()};
  }
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

Device::Device(int device_index, const Requirements& requirements) {
  instance_ = create_instance(validation_);
  try {
    physical_ = choose(physical_devices(instance_), device_index);
    vkGetPhysicalDeviceProperties(physical_, &properties_);
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    if (const std::string missing = missing_feature(physical_, requirements); !missing.empty())
      throw MissingFeature(missing);
    const int family = graphics_compute_family(physical_);
    if (family < 0)
      throw MissingFeature(fmt::format("no graphics+compute queue on {}", properties_.deviceName));
    queue_family_ = static_cast<std::uint32_t>(family);
    {
      std::uint32_t n = 0;
      vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, nullptr);
      std::vector<VkQueueFamilyProperties> families(n);
      vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, families.data());
      timestamp_bits_ = families[queue_family_].timestampValidBits;
    }
    const float priority = 1.0f;
    VkDeviceQueueCreateInfo queue{};
    queue.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
    queue.queueFamilyIndex = queue_family_;
    queue.queueCount = 1;
    queue.pQueuePriorities = &priority;
    VkPhysicalDeviceFeatures enabled{};
    enabled.tessellationShader = requirements.tessellation_shader;
    enabled.vertexPipelineStoresAndAtomics = requirements.vertex_pipeline_stores;
    enabled.pipelineStatisticsQuery = requirements.pipeline_statistics;
    enabled.geometryShader = requirements.geometry_shader;
    if (requirements.float64_when_present) {
      VkPhysicalDeviceFeatures supported;
      vkGetPhysicalDeviceFeatures(physical_, &supported);
      enabled.shaderFloat64 = supported.shaderFloat64;
      float64_ = supported.shaderFloat64 == VK_TRUE;
    }
    VkDeviceCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
    info.queueCreateInfoCount = 1;
    info.pQueueCreateInfos = &queue;
    info.pEnabledFeatures = &enabled;
    check(vkCreateDevice(physical_, &info, nullptr, &device_), "vkCreateDevice");
    vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
    VkCommandPoolCreateInfo pool{};
    pool.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
    pool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pool.queueFamilyIndex = queue_family_;
    check(vkCreateCommandPool(device_, &pool, nullptr, &pool_), "vkCreateCommandPool");
  } catch (...) {
    destroy();
    throw;
  }
}

Device::~Device() {
  destroy();
}

void Device::destroy() {
  staging_.reset();
  if (device_) {
    // Teardown: Vulkan has no bounded device-idle wait. A device lost here hangs only the
    // measurement's own process, which the run's watchdog kills (harness/isolation.h).
    vkDeviceWaitIdle(device_);
    if (fence_) vkDestroyFence(device_, fence_, nullptr);  // the command buffer goes with its pool
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  device_ = VK_NULL_HANDLE;
  pool_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
  command_buffer_ = VK_NULL_HANDLE;
  fence_ = VK_NULL_HANDLE;
}

DeviceInfo Device::record() const {
  return device_info(physical_, validation_);
}

std::vector<DeviceInfo> list_devices() {
  bool validation = false;
  VkInstance instance = create_instance(validation);
  std::vector<DeviceInfo> listed;
  try {
    const std::vector<VkPhysicalDevice> devices = physical_devices(instance);
    const VkPhysicalDevice chosen = devices.empty() ? VK_NULL_HANDLE : choose(devices, kPreferGpu);
    for (std::size_t i = 0; i < devices.size(); ++i) {
      DeviceInfo info = device_info(devices[i], validation);
      info.details["index"] = std::to_string(i);
      info.details["chosen"] = devices[i] == chosen ? "yes" : "no";
      listed.push_back(std::move(info));
    }
    // The ICDs stay loaded only while the instance lives: what they are is read now.
    if (!listed.empty()) listed.front().details["loaded_libraries"] = loaded_libraries_text();
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
  vkDestroyInstance(instance, nullptr);
  return listed;
}

void Device::submit_and_wait(const std::function<void(VkCommandBuffer)>& commands) const {
  // One command buffer and one fence, reset and reused by every submission rather than allocated
  // and freed per call, which is host work a small grid's evaluate pays in full (on an H200
  // evaluate cost 0.57-0.72 ms of wall clock for 5-13 us of device work). On lavapipe this changed
  // nothing measurable: 65-75 us beyond the device time either way, the driver's own submission and
  // fence wake-up; what it is worth on a GPU is for gpu-check to measure.
  if (!command_buffer_) {
    VkCommandBufferAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO;
    alloc.commandPool = pool_;
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    check(vkAllocateCommandBuffers(device_, &alloc, &command_buffer_), "vkAllocateCommandBuffers");
  } else {
    check(vkResetCommandBuffer(command_buffer_, 0), "vkResetCommandBuffer");
  }
  if (!fence_) {
    // A fence waited on with a bound, not vkQueueWaitIdle (which has none): a device that never
    // signals becomes DeviceTimeout, recorded as timed_out in its phase (strategies/device_wait.h).
    VkFenceCreateInfo fence_info{};
    fence_info.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO;
    check(vkCreateFence(device_, &fence_info, nullptr, &fence_), "vkCreateFence");
  } else {
    check(vkResetFences(device_, 1, &fence_), "vkResetFences");
  }
  const VkCommandBuffer cb = command_buffer_;
  VkCommandBufferBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO;
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cb, &begin), "vkBeginCommandBuffer");
  commands(cb);
  check(vkEndCommandBuffer(cb), "vkEndCommandBuffer");
  VkSubmitInfo submit{};
  submit.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO;
  submit.commandBufferCount = 1;
  submit.pCommandBuffers = &cb;
  check(vkQueueSubmit(queue_, 1, &submit, fence_), "vkQueueSubmit");
  const VkResult waited = vkWaitForFences(device_, 1, &fence_, VK_TRUE, device_wait_limit_ns());
  if (waited == VK_TIMEOUT) {
    // Still pending: a pending command buffer or fence must not be reset or freed (Vulkan's valid
    // usage). Both are left to the device's destruction, or leaked with a hung device; the next
    // submission makes new ones.
    command_buffer_ = VK_NULL_HANDLE;
    fence_ = VK_NULL_HANDLE;
    throw device_timeout("vkWaitForFences");
  }
  check(waited, "vkWaitForFences");
}

VkShaderModule Device::shader_module(std::string_view spirv) const {
  // The embedded bytes carry no alignment guarantee: copy into words.
  std::vector<std::uint32_t> words(spirv.size() / 4);
  std::memcpy(words.data(), spirv.data(), words.size() * 4);
  VkShaderModuleCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
  info.codeSize = words.size() * 4;
  info.pCode = words.data();
  VkShaderModule module = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device_, &info, nullptr, &module), "vkCreateShaderModule");
  return module;
}

int Device::memory_type(std::uint32_t type_bits, VkMemoryPropertyFlags wanted) const {
  for (std::uint32_t k = 0; k < memory_.memoryTypeCount; ++k)
    if ((type_bits & (1u << k)) && (memory_.memoryTypes[k].propertyFlags & wanted) == wanted)
      return static_cast<int>(k);
  return -1;
}

Buffer::Buffer(const Device& device, VkDeviceSize bytes, VkBufferUsageFlags usage, const char* what)
    : device_(&device), size_(bytes) {
  if (bytes > device.limits().maxStorageBufferRange && (usage & VK_BUFFER_USAGE_STORAGE_BUFFER_BIT))
    throw RefusedError(fmt::format("{} needs {} bytes, more than maxStorageBufferRange ({})", what,
                                   bytes, device.limits().maxStorageBufferRange));
  VkBufferCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
  info.size = std::max<VkDeviceSize>(bytes, 16);
  info.usage = usage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
  check(vkCreateBuffer(device.handle(), &info, nullptr, &buffer_), "vkCreateBuffer");
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device.handle(), buffer_, &req);
  // Device-local first (a real GPU); lavapipe's memory is device-local and host-visible at once.
  // A buffer with no usage of its own (usage 0) is a staging buffer: host-visible first, and
  // host-cached where there is such memory, since the host reads results through it. Each kind is
  // tried in turn when the one before has no room: a GPU's device-local, host-visible memory can be
  // a 256 MiB window (no resizable BAR) that a large output does not fit, while its plain
  // device-local heap does.
  const VkMemoryPropertyFlags host =
      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  std::vector<VkMemoryPropertyFlags> wanted;
  if (usage == 0) wanted.push_back(host | VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  wanted.push_back(VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT | host);
  if (usage == 0) wanted.push_back(host);
  wanted.push_back(VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  wanted.push_back(host);
  int type = -1;
  VkResult result = VK_ERROR_OUT_OF_DEVICE_MEMORY;
  std::vector<int> tried;
  for (const VkMemoryPropertyFlags flags : wanted) {
    const int candidate = device.memory_type(req.memoryTypeBits, flags);
    if (candidate < 0 || std::find(tried.begin(), tried.end(), candidate) != tried.end()) continue;
    tried.push_back(candidate);
    VkMemoryAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = static_cast<std::uint32_t>(candidate);
    result = vkAllocateMemory(device.handle(), &alloc, nullptr, &memory_);
    if (result == VK_SUCCESS) {
      type = candidate;
      break;
    }
    if (result != VK_ERROR_OUT_OF_DEVICE_MEMORY && result != VK_ERROR_OUT_OF_HOST_MEMORY) break;
  }
  if (type < 0) {
    reset();
    if (tried.empty()) throw std::runtime_error(fmt::format("no memory type for {}", what));
    if (result == VK_ERROR_OUT_OF_DEVICE_MEMORY || result == VK_ERROR_OUT_OF_HOST_MEMORY)
      throw RefusedError(fmt::format("{} needs {} bytes: out of device memory", what, bytes));
    check(result, "vkAllocateMemory");
  }
  check(vkBindBufferMemory(device.handle(), buffer_, memory_, 0), "vkBindBufferMemory");
  VkMemoryPropertyFlags flags = 0;
  {
    VkPhysicalDeviceMemoryProperties props;
    vkGetPhysicalDeviceMemoryProperties(device.physical(), &props);
    flags = props.memoryTypes[type].propertyFlags;
  }
  if (flags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
    check(vkMapMemory(device.handle(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
  host_cached_ = (flags & VK_MEMORY_PROPERTY_HOST_CACHED_BIT) != 0;
}

Buffer& Buffer::operator=(Buffer&& other) noexcept {
  if (this != &other) {
    reset();
    device_ = std::exchange(other.device_, nullptr);
    buffer_ = std::exchange(other.buffer_, VK_NULL_HANDLE);
    memory_ = std::exchange(other.memory_, VK_NULL_HANDLE);
    size_ = std::exchange(other.size_, 0);
    mapped_ = std::exchange(other.mapped_, nullptr);
    host_cached_ = std::exchange(other.host_cached_, false);
  }
  return *this;
}

void Buffer::reset() {
  if (!device_) return;
  if (buffer_) vkDestroyBuffer(device_->handle(), buffer_, nullptr);
  if (memory_) vkFreeMemory(device_->handle(), memory_, nullptr);  // unmaps
  buffer_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
  mapped_ = nullptr;
  size_ = 0;
}

void Buffer::write(const void* data, VkDeviceSize bytes, VkDeviceSize offset) {
  if (bytes == 0) return;
  device_->count_written(bytes);
  if (mapped_) {
    std::memcpy(static_cast<char*>(mapped_) + offset, data, bytes);
    return;
  }
  Buffer& staging = device_->staging(bytes);
  std::memcpy(staging.mapped_, data, bytes);
  device_->submit_and_wait([&](VkCommandBuffer cb) {
    const VkBufferCopy region{0, offset, bytes};
    vkCmdCopyBuffer(cb, staging.handle(), buffer_, 1, &region);
  });
}

const void* Buffer::host_view(VkDeviceSize bytes, VkDeviceSize offset) const {
  // Device-local memory that is host-visible but not host-cached (a GPU's BAR window) is read
  // uncached across the bus: 16.7M points took 8.5 s that way on an H200, so such memory is read
  // through the cached staging copy. lavapipe's memory is cached: read in place.
  if (mapped_ && host_cached_) return static_cast<const char*>(mapped_) + offset;
  Buffer& staging = device_->staging(bytes);
  if (bytes > 0)
    device_->submit_and_wait([&](VkCommandBuffer cb) {
      const VkBufferCopy region{offset, 0, bytes};
      vkCmdCopyBuffer(cb, buffer_, staging.handle(), 1, &region);
    });
  return staging.mapped_;
}

void Buffer::read(void* data, VkDeviceSize bytes, VkDeviceSize offset) const {
  if (bytes == 0) return;
  std::memcpy(data, host_view(bytes, offset), bytes);
}

Buffer& Device::staging(VkDeviceSize bytes) const {
  if (!staging_ || staging_->size() < bytes) {
    staging_.reset();  // the old one first: two large ones need not fit at once
    staging_.emplace(*this, std::max<VkDeviceSize>(bytes, 1 << 16), 0, "staging buffer");
    if (!staging_->mapped()) {
      staging_.reset();
      throw std::runtime_error("no host-visible memory for a staging buffer");
    }
  }
  return *staging_;
}

Image::Image(const Device& device, VkFormat format, VkImageUsageFlags usage,
             VkImageAspectFlags aspect, std::uint32_t width, std::uint32_t height)
    : device_(device) {
  VkImageCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO;
  info.imageType = VK_IMAGE_TYPE_2D;
  info.format = format;
  info.extent = {width, height, 1};
  info.mipLevels = 1;
  info.arrayLayers = 1;
  info.samples = VK_SAMPLE_COUNT_1_BIT;
  info.tiling = VK_IMAGE_TILING_OPTIMAL;
  info.usage = usage;
  info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  check(vkCreateImage(device.handle(), &info, nullptr, &image_), "vkCreateImage");
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(device.handle(), image_, &req);
  int type = device.memory_type(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (type < 0) type = device.memory_type(req.memoryTypeBits, 0);
  VkMemoryAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO;
  alloc.allocationSize = req.size;
  alloc.memoryTypeIndex = static_cast<std::uint32_t>(type);
  try {
    check(vkAllocateMemory(device.handle(), &alloc, nullptr, &memory_), "vkAllocateMemory");
    check(vkBindImageMemory(device.handle(), image_, memory_, 0), "vkBindImageMemory");
    VkImageViewCreateInfo view{};
    view.sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO;
    view.image = image_;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, 1, 0, 1};
    check(vkCreateImageView(device.handle(), &view, nullptr, &view_), "vkCreateImageView");
  } catch (...) {
    release();
    throw;
  }
}

Image::~Image() {
  release();
}

void Image::release() {
  if (view_) vkDestroyImageView(device_.handle(), view_, nullptr);
  if (image_) vkDestroyImage(device_.handle(), image_, nullptr);
  if (memory_) vkFreeMemory(device_.handle(), memory_, nullptr);
  view_ = VK_NULL_HANDLE;
  image_ = VK_NULL_HANDLE;
  memory_ = VK_NULL_HANDLE;
}

void memory_barrier(VkCommandBuffer cb, VkPipelineStageFlags src_stage, VkAccessFlags src_access,
                    VkPipelineStageFlags dst_stage, VkAccessFlags dst_access) {
  VkMemoryBarrier barrier{};
  barrier.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  barrier.srcAccessMask = src_access;
  barrier.dstAccessMask = dst_access;
  vkCmdPipelineBarrier(cb, src_stage, dst_stage, 0, 1, &barrier, 0, nullptr, 0, nullptr);
}

QueryPools::QueryPools(const Device& device, VkQueryPipelineStatisticFlags statistics)
    : device_(device), statistic_count_(std::popcount(statistics)) {
  period_ns_ = device.limits().timestampPeriod;
  valid_bits_ = device.timestamp_valid_bits();
  if (valid_bits_ > 0) {
    VkQueryPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    info.queryType = VK_QUERY_TYPE_TIMESTAMP;
    info.queryCount = 2;
    check(vkCreateQueryPool(device.handle(), &info, nullptr, &timestamps_), "vkCreateQueryPool");
  }
  if (statistics) {
    VkQueryPoolCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO;
    info.queryType = VK_QUERY_TYPE_PIPELINE_STATISTICS;
    info.queryCount = 1;
    info.pipelineStatistics = statistics;
    check(vkCreateQueryPool(device.handle(), &info, nullptr, &statistics_), "vkCreateQueryPool");
  }
}

QueryPools::~QueryPools() {
  if (timestamps_) vkDestroyQueryPool(device_.handle(), timestamps_, nullptr);
  if (statistics_) vkDestroyQueryPool(device_.handle(), statistics_, nullptr);
}

void QueryPools::reset(VkCommandBuffer cb) const {
  if (timestamps_) vkCmdResetQueryPool(cb, timestamps_, 0, 2);
  if (statistics_) vkCmdResetQueryPool(cb, statistics_, 0, 1);
}

void QueryPools::begin(VkCommandBuffer cb) const {
  if (timestamps_) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, timestamps_, 0);
  if (statistics_) vkCmdBeginQuery(cb, statistics_, 0, 0);
}

void QueryPools::end(VkCommandBuffer cb) const {
  if (statistics_) vkCmdEndQuery(cb, statistics_, 0);
  if (timestamps_) vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, timestamps_, 1);
}

std::optional<double> QueryPools::elapsed_s() const {
  if (!timestamps_) return std::nullopt;
  std::uint64_t t[2] = {0, 0};
  check(vkGetQueryPoolResults(device_.handle(), timestamps_, 0, 2, sizeof t, t, sizeof t[0],
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  const std::uint64_t mask =
      valid_bits_ >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << valid_bits_) - 1;
  return static_cast<double>((t[1] - t[0]) & mask) * period_ns_ * 1e-9;
}

std::vector<std::uint64_t> QueryPools::statistics() const {
  std::vector<std::uint64_t> values(statistic_count_);
  if (!statistics_ || values.empty()) return values;
  check(vkGetQueryPoolResults(device_.handle(), statistics_, 0, 1, values.size() * 8, values.data(),
                              8, VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
        "vkGetQueryPoolResults");
  return values;
}

StorageSet::StorageSet(const Device& device, const std::vector<VkShaderStageFlags>& stages)
    : device_(device) {
  const VkDevice d = device_.handle();
  const auto count = static_cast<std::uint32_t>(stages.size());
  std::vector<VkDescriptorSetLayoutBinding> bindings(count);
  for (std::uint32_t k = 0; k < count; ++k)
    bindings[k] = {k, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages[k], nullptr};
  VkDescriptorSetLayoutCreateInfo set_info{};
  set_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  set_info.bindingCount = count;
  set_info.pBindings = bindings.data();
  check(vkCreateDescriptorSetLayout(d, &set_info, nullptr, &layout_),
        "vkCreateDescriptorSetLayout");
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, count};
  VkDescriptorPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  pool_info.maxSets = 1;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &size;
  check(vkCreateDescriptorPool(d, &pool_info, nullptr, &pool_), "vkCreateDescriptorPool");
  VkDescriptorSetAllocateInfo alloc{};
  alloc.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  alloc.descriptorPool = pool_;
  alloc.descriptorSetCount = 1;
  alloc.pSetLayouts = &layout_;
  check(vkAllocateDescriptorSets(d, &alloc, &set_), "vkAllocateDescriptorSets");
}

StorageSet::~StorageSet() {
  const VkDevice d = device_.handle();
  if (pool_) vkDestroyDescriptorPool(d, pool_, nullptr);
  if (layout_) vkDestroyDescriptorSetLayout(d, layout_, nullptr);
}

ComputePipeline::ComputePipeline(const Device& device, const StorageSet& set,
                                 std::uint32_t push_bytes, std::string_view spirv, const char* what,
                                 const std::vector<std::uint32_t>& specialization)
    : device_(device) {
  const VkDevice d = device_.handle();
  const VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes};
  VkPipelineLayoutCreateInfo layout_info{};
  layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &set.layout();
  layout_info.pushConstantRangeCount = push_bytes > 0 ? 1 : 0;
  layout_info.pPushConstantRanges = &push;
  check(vkCreatePipelineLayout(d, &layout_info, nullptr, &layout_), "vkCreatePipelineLayout");
  const VkShaderModule module = device_.shader_module(spirv);
  VkComputePipelineCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO;
  info.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
  info.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  info.stage.module = module;
  info.stage.pName = "main";
  std::vector<VkSpecializationMapEntry> entries;
  for (std::uint32_t k = 0; k < specialization.size(); ++k) entries.push_back({k, k * 4u, 4u});
  const VkSpecializationInfo constants{static_cast<std::uint32_t>(entries.size()), entries.data(),
                                       specialization.size() * 4u, specialization.data()};
  if (!specialization.empty()) info.stage.pSpecializationInfo = &constants;
  info.layout = layout_;
  const VkResult created =
      vkCreateComputePipelines(d, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_);
  vkDestroyShaderModule(d, module, nullptr);
  if (created != VK_SUCCESS) {
    vkDestroyPipelineLayout(d, layout_, nullptr);
    check(created, fmt::format("vkCreateComputePipelines ({})", what).c_str());
  }
}

ComputePipeline::~ComputePipeline() {
  const VkDevice d = device_.handle();
  if (pipeline_) vkDestroyPipeline(d, pipeline_, nullptr);
  if (layout_) vkDestroyPipelineLayout(d, layout_, nullptr);
}

void ComputePipeline::bind(VkCommandBuffer cb, const StorageSet& set) const {
  vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_);
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, layout_, 0, 1, &set.handle(), 0,
                          nullptr);
}

void StorageSet::write(const std::vector<const Buffer*>& buffers) const {
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (std::size_t k = 0; k < buffers.size(); ++k) {
    infos[k] = {buffers[k]->handle(), 0, VK_WHOLE_SIZE};
    writes[k] = {};
    writes[k].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[k].dstSet = set_;
    writes[k].dstBinding = static_cast<std::uint32_t>(k);
    writes[k].descriptorCount = 1;
    writes[k].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[k].pBufferInfo = &infos[k];
  }
  vkUpdateDescriptorSets(device_.handle(), static_cast<std::uint32_t>(writes.size()), writes.data(),
                         0, nullptr);
}

}  // namespace nurbs::vulkan
