#include "strategies/link_copy.h"

#include <fmt/format.h>

#include <stdexcept>
#include <utility>

#include "strategies/device_wait.h"

#if NURBSBENCH_LINK_COPY_VULKAN
#include "strategies/vulkan/vk_device.h"
#endif
#if NURBSBENCH_LINK_COPY_OPENCL
#include "strategies/opencl/cl_device.h"
#endif
#if NURBSBENCH_LINK_COPY_GL
#include "strategies/gl_context/gl_context.h"
#endif

namespace nurbs {

// Each API's bench, defined beside that API's plumbing where it is built.
#if NURBSBENCH_LINK_COPY_VULKAN
namespace vulkan {
std::unique_ptr<LinkCopy::Bench> make_link_bench(const StrategyOptions& options);
}
#endif
#if NURBSBENCH_LINK_COPY_OPENCL
namespace opencl {
std::unique_ptr<LinkCopy::Bench> make_link_bench(const StrategyOptions& options);
}
#endif
#if NURBSBENCH_LINK_COPY_GL
namespace gl {
std::unique_ptr<LinkCopy::Bench> make_link_bench(const StrategyOptions& options);
}
#endif

std::string_view link_api_name(LinkApi api) {
  switch (api) {
    case LinkApi::vulkan:
      return "vulkan";
    case LinkApi::opencl:
      return "opencl";
    case LinkApi::gl:
      return "gl";
  }
  return "?";
}

LinkCopy::LinkCopy(LinkApi api, StrategyOptions options)
    : api_(api), options_(std::move(options)) {}

LinkCopy::~LinkCopy() = default;

const Availability& LinkCopy::availability() {
  if (availability_) return *availability_;
  switch (api_) {
    case LinkApi::vulkan:
#if NURBSBENCH_LINK_COPY_VULKAN
      availability_ = vulkan::probe(vulkan::Requirements{});
#else
      availability_ = Availability{false, "not built with Vulkan"};
#endif
      break;
    case LinkApi::opencl:
#if NURBSBENCH_LINK_COPY_OPENCL
      availability_ = opencl::probe();
#else
      availability_ = Availability{false, "not built with OpenCL"};
#endif
      break;
    case LinkApi::gl:
#if NURBSBENCH_LINK_COPY_GL
      availability_ = gl::Context::probe(gl::platform_option(options_));
#else
      availability_ = Availability{false, "not built with OpenGL"};
#endif
      break;
  }
  return *availability_;
}

namespace {

std::unique_ptr<LinkCopy::Bench> make_bench(LinkApi api, const StrategyOptions& options) {
  switch (api) {
    case LinkApi::vulkan:
#if NURBSBENCH_LINK_COPY_VULKAN
      return vulkan::make_link_bench(options);
#else
      break;
#endif
    case LinkApi::opencl:
#if NURBSBENCH_LINK_COPY_OPENCL
      return opencl::make_link_bench(options);
#else
      break;
#endif
    case LinkApi::gl:
#if NURBSBENCH_LINK_COPY_GL
      return gl::make_link_bench(options);
#else
      break;
#endif
  }
  (void)options;
  throw std::runtime_error(fmt::format("not built with {}", link_api_name(api)));
}

}  // namespace

LinkTiming LinkCopy::time(std::size_t bytes, int repetitions) {
  if (bytes == 0 || bytes % 16 != 0)
    throw std::invalid_argument(
        fmt::format("link copy: {} bytes, not a positive multiple of 16", bytes));
  return on_bench([&](Bench& bench) { return bench.time(bytes, repetitions); });
}

std::optional<PassTiming> LinkCopy::fragment_pass(std::size_t pixels, int repetitions) {
  if (pixels == 0) throw std::invalid_argument("fragment pass: no pixels");
  return on_bench([&](Bench& bench) { return bench.fragment_pass(pixels, repetitions); });
}

template <typename F>
auto LinkCopy::on_bench(F&& f) -> decltype(f(std::declval<Bench&>())) {
  try {
    if (!bench_) bench_ = make_bench(api_, options_);
    return f(*bench_);
  } catch (const DeviceTimeout& e) {
    // A device that stopped answering cannot be torn down without an unbounded wait: it is left
    // as it is, and the run's later rows for this API are unavailable instead of each waiting out
    // the limit again.
    static_cast<void>(bench_.release());
    availability_ = Availability{
        false, fmt::format("the device did not answer an earlier copy of this run: {}", e.what())};
    throw;
  } catch (...) {
    bench_.reset();  // the device's state is unknown: the next copy opens it again
    throw;
  }
}

}  // namespace nurbs
