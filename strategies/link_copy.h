// The host<->device link of each GPU API, the ceiling a strategy's upload and read_back phases run
// into, measured in the same run as the strategies (harness/link_limit.h turns it into the rows
// limit-link-vulkan, limit-link-opencl and limit-link-gl). A GPU strategy's results cross the link
// once per read-back: before these rows nothing said whether a 0.2 GB/s read-back was the bus or
// our code (it was our code: a fresh staging buffer per call, pageable targets, a host repack).
// This front keeps the harness free of any API's headers, as strategies/device_copy.h does.
//
// What each API's row times, the way a well-written strategy on that API would move the bytes:
// between memory the device reaches directly (Vulkan: a host-visible, host-cached buffer; OpenCL:
// a CL_MEM_ALLOC_HOST_PTR buffer mapped once; GL: a pixel-pack/unpack buffer object mapped for the
// copy) and device memory (a device-local buffer, an OpenCL buffer, a GL texture or framebuffer),
// allocated once and reused, wall clock around submission and completion (what a strategy's phase
// pays), every repetition all the bytes. On lavapipe, PoCL and llvmpipe device memory is host
// memory and the rows are a CPU figure, labelled so by their device.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "strategies/strategy.h"

namespace nurbs {

enum class LinkApi { vulkan, opencl, gl };
inline constexpr LinkApi kLinkApis[] = {LinkApi::vulkan, LinkApi::opencl, LinkApi::gl};
// "vulkan", "opencl", "gl": the suffix of the row's name.
std::string_view link_api_name(LinkApi api);

struct LinkTiming {
  DeviceInfo device;                // the device, as its strategies record it
  double setup_s = 0;               // the device (first use of a session), buffers, untimed copies
  std::vector<double> upload_s;     // host -> device, all the bytes, one per repetition
  std::vector<double> read_back_s;  // device -> host, all the bytes, one per repetition
  std::string method;               // what was timed, in words, for the record
};

// A device's own ceiling for the work of a strategy's kind, where the API has one: for GL, one
// trivial fragment pass (a constant colour, no reads) writing as many RGBA32F pixels as the
// request has points, the format the GL strategies' passes write. Its points/s are the most a GL
// strategy's evaluate could reach if writing its output pixels once were all it did: a GPU's
// graphics part can be far smaller than its compute (3.3-3.5 G fragments/s on an H200).
struct PassTiming {
  DeviceInfo device;
  std::vector<double> seconds;         // wall clock, all the pixels, one per repetition
  std::vector<double> device_seconds;  // the device's timer for the same passes, where it has one
  std::string method;
};

// One API's copies for a run: the device is opened on the first use and kept with its buffers
// (grown for a larger request, never shrunk); a copy that throws drops them, so the next use opens
// a fresh device, and one that timed out leaves the device alone and makes the later rows
// unavailable (its teardown could wait forever).
class LinkCopy {
 public:
  // What each API's implementation provides (strategies/<api plumbing>/*_link_bandwidth.cpp).
  class Bench {
   public:
    virtual ~Bench() = default;
    // `repetitions` copies of `bytes` (a positive multiple of 16) each way after an untimed one
    // each way; the content is checked after the last of each (a copy that did not happen is an
    // error, not a fast row). Throws std::runtime_error, RefusedError (does not fit),
    // DeviceTimeout.
    virtual LinkTiming time(std::size_t bytes, int repetitions) = 0;
    // `repetitions` passes writing `pixels` pixels after an untimed one, their output checked;
    // nullopt where the API has no such ceiling (only GL has one).
    virtual std::optional<PassTiming> fragment_pass(std::size_t pixels, int repetitions) {
      (void)pixels, (void)repetitions;
      return std::nullopt;
    }
  };

  LinkCopy(LinkApi api, StrategyOptions options);
  ~LinkCopy();
  LinkCopy(const LinkCopy&) = delete;
  LinkCopy& operator=(const LinkCopy&) = delete;

  LinkApi api() const { return api_; }
  // Whether the API has a device here ("not built with ...", or the API's probe's reason).
  const Availability& availability();
  LinkTiming time(std::size_t bytes, int repetitions);
  // The API's fragment-pass ceiling on the same device (Bench::fragment_pass), with time()'s
  // handling of failures and timeouts.
  std::optional<PassTiming> fragment_pass(std::size_t pixels, int repetitions);

 private:
  // Runs `f` on the bench (made on the first use); a timeout leaves the device alone and makes
  // the later rows unavailable, any other failure drops the bench for the next use to remake.
  template <typename F>
  auto on_bench(F&& f) -> decltype(f(std::declval<Bench&>()));

  LinkApi api_;
  StrategyOptions options_;
  std::optional<Availability> availability_;
  std::unique_ptr<Bench> bench_;
};

}  // namespace nurbs
