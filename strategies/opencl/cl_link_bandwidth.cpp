// The limit-link-opencl row's copies (strategies/link_copy.h): between pinned host memory
// (PinnedHost: a CL_MEM_ALLOC_HOST_PTR buffer mapped once) and a device buffer, as cl-stair and
// cl-tspline-bezier move their uploads and staged read-backs.
#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>

#include "strategies/link_copy.h"
#include "strategies/opencl/cl_device.h"
#include "strategies/opencl/cl_pinned.h"
#include "strategies/wall_clock.h"

namespace nurbs::opencl {
namespace {

class LinkBench final : public LinkCopy::Bench {
 public:
  explicit LinkBench(int device_index) {
    device_setup_s_ = wall_seconds([&] {
      ctx_.emplace(device_index);
      host_.emplace(*ctx_);
    });
  }
  ~LinkBench() override {
    host_.reset();
    if (device_) clReleaseMemObject(device_);
  }

  LinkTiming time(std::size_t bytes, int repetitions) override {
    LinkTiming out;
    out.device = ctx_->record();
    out.method = fmt::format(
        "clEnqueueWriteBuffer / clEnqueueReadBuffer of all {} bytes between pinned host memory (a "
        "CL_MEM_ALLOC_HOST_PTR buffer mapped once) and a device buffer, both kept for the run; "
        "wall clock around the non-blocking enqueue and the bounded completion wait",
        bytes);
    void* host = nullptr;
    out.setup_s = device_setup_s_ + wall_seconds([&] {
                    host = host_->reserve(bytes, "link copy (pinned host memory)");
                    ensure_buffer(*ctx_, &device_, &capacity_, CL_MEM_READ_WRITE, bytes,
                                  "link copy (device buffer)");
                  });
    device_setup_s_ = 0;
    // Copy 0 of each direction is untimed (first touches, lazy allocation); a new word is written
    // before the last one, and words of its destination are checked after it: a copy that did not
    // happen is an error, not a fast row.
    const std::uint32_t up_word = next_word(), down_word = next_word();
    for (int k = 0; k <= repetitions; ++k) {
      if (k == repetitions) fill_host(host, bytes, up_word);
      const double s =
          wall_seconds([&] { write(*ctx_, device_, host, bytes, "link copy (upload)"); });
      if (k > 0) out.upload_s.push_back(s);
    }
    check_device(bytes, up_word);
    for (int k = 0; k <= repetitions; ++k) {
      if (k == repetitions) fill_device(bytes, down_word);
      const double s =
          wall_seconds([&] { read(*ctx_, device_, host, bytes, "link copy (read-back)"); });
      if (k > 0) out.read_back_s.push_back(s);
    }
    check_host(host, bytes, down_word);
    return out;
  }

 private:
  // Words no earlier copy of this bench wrote (nor zero, what fresh memory may hold).
  std::uint32_t next_word() { return 0x5eed0000u + ++words_; }

  static void fill_host(void* host, std::size_t bytes, std::uint32_t word) {
    auto* w = static_cast<std::uint32_t*>(host);
    for (std::size_t k = 0; k < bytes / 4; ++k) w[k] = word;
  }

  void fill_device(std::size_t bytes, std::uint32_t word) {
    Batch batch;
    check(clEnqueueFillBuffer(ctx_->queue(), device_, &word, sizeof word, 0, bytes, 0, nullptr,
                              batch.next()),
          "clEnqueueFillBuffer (link copy)");
    batch.wait("clEnqueueFillBuffer (link copy)");
  }

  // The first, a middle and the last word.
  static std::size_t checked_offset(int k, std::size_t bytes) {
    return k == 0 ? 0 : k == 1 ? bytes / 8 * 4 : bytes - 4;
  }

  void check_device(std::size_t bytes, std::uint32_t word) {
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = checked_offset(k, bytes);
      std::uint32_t got = 0;
      Batch batch;
      enqueue_read(batch, *ctx_, device_, at, &got, sizeof got, "link copy (check)");
      batch.wait("link copy (check)");
      expect(got, word, at, "upload");
    }
  }

  static void check_host(const void* host, std::size_t bytes, std::uint32_t word) {
    for (int k = 0; k < 3; ++k) {
      const std::size_t at = checked_offset(k, bytes);
      std::uint32_t got = 0;
      std::memcpy(&got, static_cast<const unsigned char*>(host) + at, sizeof got);
      expect(got, word, at, "read-back");
    }
  }

  static void expect(std::uint32_t got, std::uint32_t word, std::size_t at, const char* copy) {
    if (got != word)
      throw std::runtime_error(
          fmt::format("the OpenCL {} copy did not arrive: word at byte {} is {:#x}, expected {:#x}",
                      copy, at, got, word));
  }

  double device_setup_s_ = 0;  // reported with the first timing
  std::optional<Context> ctx_;
  std::optional<PinnedHost> host_;
  cl_mem device_ = nullptr;
  std::size_t capacity_ = 0;
  std::uint32_t words_ = 0;
};

}  // namespace

std::unique_ptr<LinkCopy::Bench> make_link_bench(const StrategyOptions& options) {
  return std::make_unique<LinkBench>(device_option(options));
}

}  // namespace nurbs::opencl
