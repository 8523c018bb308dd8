#include "harness/store_limit.h"

#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <string>
#include <vector>

#include "harness/machine.h"
#include "harness/timing.h"
#include "strategies/device_wait.h"

namespace nurbs {

namespace {

template <typename T>
void store(T* data, std::size_t values, T value) {
  // STREAM-like store kernel; schedule(static) gives each thread one contiguous share, as a grid
  // evaluator splitting rows across threads writes its output.
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < values; ++i) data[i] = value;
}

}  // namespace

double time_store_pass(void* buffer, std::size_t values, std::size_t scalar_bytes, int pass) {
  return time_seconds([&] {
    if (scalar_bytes == sizeof(float))
      store(static_cast<float*>(buffer), values, static_cast<float>(pass + 1));
    else
      store(static_cast<double*>(buffer), values, static_cast<double>(pass + 1));
    // The stores must happen: the buffer escapes to an opaque barrier the optimiser cannot see
    // through.
    asm volatile("" : : "r"(buffer) : "memory");
  });
}

std::size_t last_level_cache_bytes() {
  std::size_t largest = 0;
  // index0..: L1d, L1i, L2, L3 on x86; the highest level present is the last.
  for (int index = 0; index < 8; ++index) {
    std::ifstream in(fmt::format("/sys/devices/system/cpu/cpu0/cache/index{}/size", index));
    std::string text;
    if (!(in >> text) || text.empty()) continue;
    std::size_t scale = 1;
    if (text.back() == 'K') scale = std::size_t{1} << 10;
    if (text.back() == 'M') scale = std::size_t{1} << 20;
    try {
      largest = std::max(largest, static_cast<std::size_t>(std::stoull(text)) * scale);
    } catch (const std::exception&) {
      continue;  // an unreadable size: not a cache level we can use
    }
  }
  if (largest == 0) {
    // No sysfs cache directory (this 2-core guest has none): the CPUID figure glibc reports.
    const long l3 = sysconf(_SC_LEVEL3_CACHE_SIZE);
    if (l3 > 0) largest = static_cast<std::size_t>(l3);
  }
  return largest;
}

std::size_t store_pass_bytes(std::size_t result_bytes) {
  // At most 128 MiB: a guest may report its host's whole L3 (508 MiB on the 2-core EPYC guest,
  // summed over core complexes, of which a core's writes fill only its own: 32 or 96 MiB on
  // current EPYCs), and every limit row (and the tests that make them) pays the pass; 4x a 512 MiB
  // figure made harness_test's store-limit case 60x slower.
  static const std::size_t floor = std::clamp<std::size_t>(
      4 * last_level_cache_bytes(), std::size_t{64} << 20, std::size_t{128} << 20);
  return std::max(result_bytes, floor);
}

std::size_t result_bytes_per_point(const EvalRequest& request) {
  const std::size_t scalar = request.precision == Precision::f32 ? sizeof(float) : sizeof(double);
  return (request.normals ? 6 : 3) * scalar;
}

Record limit_record(std::string_view name, const Scene& scene, const EvalRequest& request,
                    int repetitions) {
  Record r;
  r.scene = scene.name;
  r.strategy = std::string(name);
  r.role = "limit";
  r.precision = std::string(to_string(request.precision));
  r.sampling = sampling_mode_name(request.sampling.mode);
  r.samples = request.sampling.label();
  r.points = total_samples(sample_parameters(scene, request.sampling));
  r.surfaces = scene.surfaces.size();
  r.repetitions = repetitions;
  return r;
}

void set_limit_seconds(Record& r, std::vector<double> seconds, std::size_t pass_bytes,
                       std::size_t bytes_per_point) {
  // The pass moved `pass_bytes`; the request's points would have been written in the share of its
  // time their bytes are of it.
  const double share =
      static_cast<double>(r.points * bytes_per_point) / static_cast<double>(pass_bytes);
  for (double& s : seconds) s *= share;
  r.evaluate = PhaseStats::of(seconds);
  r.throughput_pts_per_s = r.evaluate.median_s > 0 ? r.points / r.evaluate.median_s : 0;
  r.figures["pass_bytes"] = static_cast<double>(pass_bytes);
  r.figures["bytes_per_point"] = static_cast<double>(bytes_per_point);
  r.status = Status::ok;
}

Record measure_store_limit(const Scene& scene, const EvalRequest& request, int repetitions) {
  Record r = limit_record(kStoreLimitName, scene, request, repetitions);
  r.device = {
      fmt::format("host CPU ({})", cpu_model()),
      "cpu",
      {{"threads", std::to_string(omp_get_max_threads())},
       {"kernel",
        "OpenMP static store loop (STREAM-like), one share per thread, over at least 4x the "
        "last-level cache"}}};
  const std::size_t scalar = request.precision == Precision::f32 ? sizeof(float) : sizeof(double);
  const std::size_t bytes_per_point = result_bytes_per_point(request);
  const std::size_t bytes = store_pass_bytes(r.points * bytes_per_point);
  const std::size_t values = bytes / scalar;
  // Allocated and first touched outside the timing: a strategy's output buffer is allocated once.
  std::vector<unsigned char> buffer(values * scalar);
  r.setup_s = time_store_pass(buffer.data(), values, scalar, 0);
  // The first pass also paid the page faults and, first in a process, the pool's thread creation;
  // one more, untimed, so the first timed pass finds the threads awake and the pages mapped, as a
  // strategy's repeated evaluations do.
  time_store_pass(buffer.data(), values, scalar, 0);
  std::vector<double> seconds;
  for (int i = 0; i < repetitions; ++i)
    seconds.push_back(time_store_pass(buffer.data(), values, scalar, i + 1));
  set_limit_seconds(r, std::move(seconds), bytes, bytes_per_point);
  r.figures["store_bytes_per_s"] = r.throughput_pts_per_s * static_cast<double>(bytes_per_point);
  return r;
}

void measure_on_device(Record& r, const Availability& availability,
                       const std::function<void()>& measure) {
  if (!availability.available) {
    r.status = Status::unavailable;
    r.reason = availability.reason;
    return;
  }
  try {
    measure();
  } catch (const RefusedError& e) {
    r.status = Status::refused;
    r.reason = e.what();
  } catch (const DeviceTimeout& e) {
    r.status = Status::timed_out;
    r.reason = fmt::format("in the copy: {}", e.what());
  } catch (const std::exception& e) {
    r.status = Status::failed;
    r.reason = e.what();
  }
}

const Record* limit_row_for(const Record& r, const std::vector<Record>& records,
                            std::string_view limit_name) {
  if (r.role == "limit" || r.status != Status::ok) return nullptr;
  const Record* found = nullptr;
  for (const Record& l : records)
    if (l.strategy == limit_name && l.status == Status::ok && l.scene == r.scene &&
        l.samples == r.samples && l.precision == r.precision && l.throughput_pts_per_s > 0)
      found = &l;
  return found;
}

const Record* limit_row_on_device(const Record& r, const std::vector<Record>& records,
                                  std::string_view limit_name) {
  const Record* limit = limit_row_for(r, records, limit_name);
  return limit && limit->device.name == r.device.name ? limit : nullptr;
}

bool limit_too_small(const Record& limit) {
  const auto bytes = limit.figures.find("bytes_per_point");
  // A row without the figure (older results) is judged as holding 12 bytes a point, f32 xyz, the
  // least any request writes.
  const double per_point = bytes != limit.figures.end() ? bytes->second : 12.0;
  return static_cast<double>(limit.points) * per_point < static_cast<double>(kStoreLimitMinBytes);
}

std::optional<double> fraction_of_store_limit(const Record& r, const std::vector<Record>& records) {
  // The host's store bandwidth bounds what the host writes: a GPU writes its own memory, and its
  // throughput over the host's stores ("130%" on an H200) is no fraction of anything.
  if (r.device.kind != "cpu") return std::nullopt;
  const Record* limit = limit_row_for(r, records, kStoreLimitName);
  if (!limit || limit_too_small(*limit)) return std::nullopt;
  return r.throughput_pts_per_s / limit->throughput_pts_per_s;
}

bool store_limit_too_small(const Record& r, const std::vector<Record>& records) {
  if (r.device.kind != "cpu") return false;
  const Record* limit = limit_row_for(r, records, kStoreLimitName);
  return limit && limit_too_small(*limit);
}

}  // namespace nurbs
