// What each GPU API finds on this machine, for `nurbsbench list`: every device the API offers (a
// real GPU or a software stand-in), the one the strategies use without --device, the shared
// libraries its loader pulled in (so the ICD or vendor library that served it can be named), and
// why there is none. Enumeration lives in each API's plumbing; this gathers the three.
#pragma once

#include <string>
#include <vector>

#include "strategies/strategy.h"

namespace nurbs {

struct ApiDevices {
  std::string api;                  // "Vulkan", "OpenCL", "OpenGL (EGL)"
  std::string unavailable;          // why no device: not built, no loader, no driver; else empty
  std::vector<DeviceInfo> devices;  // details "index" and "chosen" ("yes" for the default pick)
  std::vector<std::string> loaded_libraries;  // paths, read while the API's driver was loaded
};

std::vector<ApiDevices> gpu_api_devices();

// The paths of every shared object loaded in this process now, newline-separated (a DeviceInfo
// detail is a string): read by an API's enumeration while its driver is loaded.
std::string loaded_libraries_text();

}  // namespace nurbs
