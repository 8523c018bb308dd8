// The bound on every wait for a device (docs/design.md §Reliability rules: every device wait has a
// bound). A driver that never signals a fence, sync object or event must become a result, not a
// hang: the GL, Vulkan and OpenCL plumbing wait at most device_wait_limit_s() and then throw
// DeviceTimeout, which the runner records as timed_out with the phase it was in.
#pragma once

#include <fmt/format.h>

#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace nurbs {

class DeviceTimeout : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Process-wide like the thread setting: the CLI sets it once (--device-timeout) before any
// strategy exists, and a measurement's child process from its spec. Default 60 s: far above any
// single submission of the project's workloads on a software driver, far below the run's
// per-measurement watchdog (600 s), so a lost device names its API call instead of the watchdog
// naming only the phase.
inline double& device_wait_limit_s() {
  static double seconds = 60;
  return seconds;
}

// The limit as the nanosecond timeouts of vkWaitForFences and glClientWaitSync take it.
inline std::uint64_t device_wait_limit_ns() {
  const double ns = device_wait_limit_s() * 1e9;
  return ns >= 1.8e19 ? UINT64_MAX : static_cast<std::uint64_t>(ns);
}

inline std::chrono::steady_clock::time_point device_wait_deadline() {
  return std::chrono::steady_clock::now() +
         std::chrono::duration_cast<std::chrono::steady_clock::duration>(
             std::chrono::duration<double>(device_wait_limit_s()));
}

// The one message every backend throws, so results read alike.
inline DeviceTimeout device_timeout(const std::string& wait) {
  return DeviceTimeout(
      fmt::format("{}: the device did not answer within {:g} s", wait, device_wait_limit_s()));
}

}  // namespace nurbs
