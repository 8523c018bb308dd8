#include "strategies/gpu_devices.h"

#include <link.h>

#include <exception>
#include <sstream>

#if NURBSBENCH_GPU_DEVICES_GL
#include "strategies/gl_context/gl_context.h"
#endif
#if NURBSBENCH_GPU_DEVICES_OPENCL
#include "strategies/opencl/cl_device.h"
#endif
#if NURBSBENCH_GPU_DEVICES_VULKAN
#include "strategies/vulkan/vk_device.h"
#endif

namespace nurbs {
namespace {

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

// Runs one API's enumeration; a throw (no loader, no driver, no device) becomes the reason.
template <typename List>
ApiDevices enumerate(std::string api, List list) {
  ApiDevices result{std::move(api), {}, {}, {}};
  try {
    result.devices = list();
    if (result.devices.empty()) result.unavailable = "no device";
  } catch (const std::exception& e) {
    result.unavailable = e.what();
  }
  if (!result.devices.empty()) {
    auto& details = result.devices.front().details;
    if (auto it = details.find("loaded_libraries"); it != details.end()) {
      result.loaded_libraries = split_lines(it->second);
      details.erase(it);
    }
  }
  return result;
}

}  // namespace

std::string loaded_libraries_text() {
  std::string text;
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* out) {
        if (info->dlpi_name && info->dlpi_name[0])
          *static_cast<std::string*>(out) += std::string(info->dlpi_name) + "\n";
        return 0;
      },
      &text);
  return text;
}

std::vector<ApiDevices> gpu_api_devices() {
  std::vector<ApiDevices> apis;
#if NURBSBENCH_GPU_DEVICES_VULKAN
  apis.push_back(enumerate("Vulkan", [] { return vulkan::list_devices(); }));
#else
  apis.push_back({"Vulkan", "not built with Vulkan", {}, {}});
#endif
#if NURBSBENCH_GPU_DEVICES_GL
  // The GL strategies' own choice: EGL's first hardware device, else its surfaceless platform.
  apis.push_back(enumerate("OpenGL (EGL)", [] {
    std::unique_ptr<gl::Context> context = gl::Context::create(gl::Platform::egl);
    DeviceInfo info = context->device_info();
    info.details["chosen"] = "yes";
    info.details["loaded_libraries"] = loaded_libraries_text();
    return std::vector<DeviceInfo>{info};
  }));
#else
  apis.push_back({"OpenGL (EGL)", "not built with OpenGL", {}, {}});
#endif
#if NURBSBENCH_GPU_DEVICES_OPENCL
  apis.push_back(enumerate("OpenCL", [] { return opencl::list_devices(); }));
#else
  apis.push_back({"OpenCL", "not built with OpenCL", {}, {}});
#endif
  return apis;
}

}  // namespace nurbs
