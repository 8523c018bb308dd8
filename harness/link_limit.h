// The host<->device link of each GPU API as rows of the run (limit-link-vulkan, limit-link-opencl,
// limit-link-gl; strategies/link_copy.h says what each times): the ceiling of a GPU strategy's
// upload and read_back phases, measured in the same run, on the same device, for the same bytes
// as the request's result. Without it a read-back at 0.2 GB/s could not be told from the bus; with
// it each strategy's transfer phases read as a fraction of what the API's own best copy of those
// bytes takes. Its read_back and upload phases hold one copy of the request's result bytes each
// way (positions, and normals when asked, at the precision); its points/s are those of the
// read-back; figures read_back_bytes_per_s, upload_bytes_per_s, bytes. On lavapipe, PoCL and
// llvmpipe device memory is host memory: a CPU figure, labelled so by its device.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "harness/record.h"
#include "reference/surface.h"
#include "strategies/link_copy.h"
#include "strategies/strategy.h"

namespace nurbs {

inline constexpr std::string_view kLinkLimitPrefix = "limit-link-";

// "limit-link-vulkan" etc.
std::string link_limit_name(LinkApi api);
// The API whose link `name` is, when it names one of the rows.
std::optional<LinkApi> link_limit_api(std::string_view name);

// The API a strategy's device record belongs to, read from the details each API's plumbing
// records ("api" = "Vulkan ..."; OpenCL's "platform"; GL's "gl_version"); none for host strategies.
std::optional<LinkApi> link_api_of(const DeviceInfo& device);

// The row for `scene` and `request` on `link`'s device: `repetitions` copies each way of the
// request's result bytes. Never throws for the device's sake: a missing API or device is
// unavailable, a refused allocation refused, a hang timed_out, a wrong copy failed.
Record measure_link_limit(const Scene& scene, const EvalRequest& request, int repetitions,
                          LinkCopy& link);

// The GL paths' own ceiling (strategies/link_copy.h, PassTiming): limit-gl-fragment-pass, one
// trivial fragment pass writing as many RGBA32F pixels as the request has points, on the GL
// device the GL strategies use. Its evaluate phase is the pass (wall clock, the GL strategies'
// evaluate clock; the device's timer in device_evaluate_median_s), its points/s the most a GL
// strategy's evaluate could reach if writing its output pixels once were all it did.
inline constexpr std::string_view kFragmentPassLimitName = "limit-gl-fragment-pass";
Record measure_fragment_pass_limit(const Scene& scene, const EvalRequest& request, int repetitions,
                                   LinkCopy& gl_link);
// `r`'s points/s over that row's for the same scene, samples and precision, for a GL strategy on
// the same device; none otherwise.
std::optional<double> fraction_of_fragment_pass(const Record& r,
                                                const std::vector<Record>& records);

// Which transfer phase of a strategy a fraction is about.
enum class LinkPhase { upload, read_back };

// `r`'s phase as a fraction of its API's link row for the same scene, samples and precision on
// the same device: read_back = the row's read-back time of the result bytes over r's read_back
// median (the bytes r delivers are the row's); upload = r's upload bandwidth (its device detail
// "bytes_uploaded" over its upload median) over the row's upload bandwidth. None when there is no
// such row, r is a limit row, not ok, on another device, or (upload) says nothing of its bytes.
std::optional<double> fraction_of_link(const Record& r, const std::vector<Record>& records,
                                       LinkPhase phase);

}  // namespace nurbs
