#include "harness/link_limit.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <stdexcept>

#include "harness/store_limit.h"

namespace nurbs {

std::string link_limit_name(LinkApi api) {
  return fmt::format("{}{}", kLinkLimitPrefix, link_api_name(api));
}

std::optional<LinkApi> link_limit_api(std::string_view name) {
  for (const LinkApi api : kLinkApis)
    if (name == link_limit_name(api)) return api;
  return std::nullopt;
}

std::optional<LinkApi> link_api_of(const DeviceInfo& device) {
  const auto has = [&](const char* key) { return device.details.count(key) > 0; };
  const auto api = device.details.find("api");
  if (api != device.details.end() && api->second.starts_with("Vulkan")) return LinkApi::vulkan;
  if (has("platform") && has("device_version")) return LinkApi::opencl;
  if (has("gl_version")) return LinkApi::gl;
  return std::nullopt;
}

Record measure_link_limit(const Scene& scene, const EvalRequest& request, int repetitions,
                          LinkCopy& link) {
  Record r = limit_record(link_limit_name(link.api()), scene, request, repetitions);
  const std::size_t bytes_per_point = result_bytes_per_point(request);
  // The result's own bytes, rounded up to what every API copies whole: a small grid's transfer
  // is mostly the call's fixed cost, which a strategy's read-back of the same result pays too.
  const std::size_t result_bytes = r.points * bytes_per_point;
  const std::size_t bytes = (std::max<std::size_t>(result_bytes, 16) + 15) / 16 * 16;
  measure_on_device(r, link.availability(), [&] {
    LinkTiming t = link.time(bytes, repetitions);
    r.device = std::move(t.device);
    r.device.details["kernel"] = t.method;
    r.device.details["clock"] = "host wall clock around submission and completion";
    r.setup_s = t.setup_s;
    // Scaled to the result's bytes from the rounded-up copy (at most 15 bytes more).
    const double share = static_cast<double>(result_bytes) / static_cast<double>(bytes);
    for (double& s : t.upload_s) s *= share;
    for (double& s : t.read_back_s) s *= share;
    r.upload = PhaseStats::of(t.upload_s);
    r.read_back = PhaseStats::of(t.read_back_s);
    r.throughput_pts_per_s = r.read_back.median_s > 0 ? r.points / r.read_back.median_s : 0;
    r.figures["bytes"] = static_cast<double>(result_bytes);
    r.figures["bytes_per_point"] = static_cast<double>(bytes_per_point);
    if (r.read_back.median_s > 0)
      r.figures["read_back_bytes_per_s"] = static_cast<double>(result_bytes) / r.read_back.median_s;
    if (r.upload.median_s > 0)
      r.figures["upload_bytes_per_s"] = static_cast<double>(result_bytes) / r.upload.median_s;
    r.status = Status::ok;
  });
  return r;
}

Record measure_fragment_pass_limit(const Scene& scene, const EvalRequest& request, int repetitions,
                                   LinkCopy& gl_link) {
  Record r = limit_record(kFragmentPassLimitName, scene, request, repetitions);
  measure_on_device(r, gl_link.availability(), [&] {
    std::optional<PassTiming> t =
        gl_link.fragment_pass(std::max<std::size_t>(r.points, 1), repetitions);
    if (!t) throw std::runtime_error("this API has no fragment pass");
    r.device = std::move(t->device);
    r.device.details["kernel"] = t->method;
    r.evaluate = PhaseStats::of(t->seconds);
    if (!t->device_seconds.empty())
      r.device_evaluate_median_s = PhaseStats::of(t->device_seconds).median_s;
    r.throughput_pts_per_s = r.evaluate.median_s > 0 ? r.points / r.evaluate.median_s : 0;
    r.figures["pixels"] = static_cast<double>(r.points);
    r.status = Status::ok;
  });
  return r;
}

std::optional<double> fraction_of_fragment_pass(const Record& r,
                                                const std::vector<Record>& records) {
  if (link_api_of(r.device) != LinkApi::gl) return std::nullopt;
  const Record* limit = limit_row_on_device(r, records, kFragmentPassLimitName);
  if (!limit) return std::nullopt;
  return r.throughput_pts_per_s / limit->throughput_pts_per_s;
}

std::optional<double> fraction_of_link(const Record& r, const std::vector<Record>& records,
                                       LinkPhase phase) {
  const std::optional<LinkApi> api = link_api_of(r.device);
  if (!api) return std::nullopt;
  const Record* limit = limit_row_on_device(r, records, link_limit_name(*api));
  if (!limit) return std::nullopt;
  if (phase == LinkPhase::read_back) {
    if (!(r.read_back.median_s > 0) || !(limit->read_back.median_s > 0)) return std::nullopt;
    return limit->read_back.median_s / r.read_back.median_s;
  }
  const auto bytes = r.device.details.find("bytes_uploaded");
  const auto link_rate = limit->figures.find("upload_bytes_per_s");
  if (bytes == r.device.details.end() || link_rate == limit->figures.end() ||
      !(r.upload.median_s > 0) || !(link_rate->second > 0))
    return std::nullopt;
  double uploaded = 0;
  const std::string& text = bytes->second;
  if (std::from_chars(text.data(), text.data() + text.size(), uploaded).ec != std::errc() ||
      !(uploaded > 0))
    return std::nullopt;
  return uploaded / r.upload.median_s / link_rate->second;
}

}  // namespace nurbs
