// The memory-write ceiling a grid evaluator's output stream runs into, measured in the same run
// as the strategies (issue 6: "cpu-tensor f32 >= 50% of the machine's memory write bandwidth").
// Every thread (the run's one thread setting) stores into its own share of a buffer at least the
// size of the request's result, points x (3, or 6 with normals) x the precision's scalar size,
// and larger than the last-level cache (store_pass_bytes). The record
// it yields is a row like a strategy's, of role "limit": its throughput is the points per second
// a strategy would reach if writing its results were all it did; it evaluates nothing and has no
// accuracy.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string_view>
#include <vector>

#include "harness/record.h"
#include "reference/surface.h"
#include "strategies/strategy.h"

namespace nurbs {

inline constexpr std::string_view kStoreLimitName = "limit-store-bandwidth";

// Below this much output a store pass measures the parallel region's fork and join, not the
// memory: on the canonical 2-thread EPYC a pass takes ~3.3 us flat from 16 points to 64x64 f32
// (48 KiB), still a third of the time at 256x256 f32 (768 KiB), and a loaded machine's thread
// wake-ups cost milliseconds. "Of store limit" is left out under it.
inline constexpr std::size_t kStoreLimitMinBytes = std::size_t{1} << 20;

// The bytes one store pass writes for a result of `result_bytes`: the result, but never less than
// four times the last-level cache (sysfs, else CPUID via sysconf; within [64 MiB, 128 MiB]), so the
// pass always measures what a result costs in memory, a write-back to DRAM per line, and "of the
// store limit" means the same at every size. Chosen over a pass over the strategy's own output
// (the harness would need every strategy's buffer) and over non-temporal stores (they beat
// ordinary stores on some machines and lose on others, so the limit would depend on a store kind
// no strategy is obliged to use). A result that fits in the cache is thus held against DRAM
// bandwidth, not against the cache's: the cache-sized pass flattered nothing but made small grids'
// fractions come out low for no fault of the strategy, and large ones high by comparison.
std::size_t store_pass_bytes(std::size_t result_bytes);
// The last-level cache of cpu0 in bytes (sysfs, else sysconf's CPUID figure), 0 when unknown.
std::size_t last_level_cache_bytes();

// Seconds to store `values` scalars of `scalar_bytes` each (4 or 8) into `buffer`, every thread
// its own contiguous share; `pass` changes the stored value so no pass can be elided.
double time_store_pass(void* buffer, std::size_t values, std::size_t scalar_bytes, int pass);

// Bytes a strategy writes per sample for `request` (positions, plus normals when asked).
std::size_t result_bytes_per_point(const EvalRequest& request);

// The limit row for `scene` and `request`: `repetitions` store passes of store_pass_bytes() after a
// first-touch pass and a warm-up pass, both untimed; its points/s are the pass's bytes/s over the
// request's bytes a point. figures: bytes_per_point, store_bytes_per_s, pass_bytes.
Record measure_store_limit(const Scene& scene, const EvalRequest& request, int repetitions);

// The parts every limit row shares. limit_record: a row of role "limit" named `name` for `scene`
// and `request`, nothing measured yet. set_limit_seconds: its evaluate phase and points/s from
// `seconds` of passes that each moved `pass_bytes`, scaled to the request's share of them
// (points x `bytes_per_point`), figures pass_bytes and bytes_per_point, status ok.
Record limit_record(std::string_view name, const Scene& scene, const EvalRequest& request,
                    int repetitions);
void set_limit_seconds(Record& r, std::vector<double> seconds, std::size_t pass_bytes,
                       std::size_t bytes_per_point);
// Runs `measure`, which fills the limit row `r` on a device, and records what a device can do
// instead as the row's status: no device (`availability`) unavailable, a refused allocation
// refused, a wait that expired timed_out, any other error failed, each with its reason. Never
// throws.
void measure_on_device(Record& r, const Availability& availability,
                       const std::function<void()>& measure);
// The last ok row named `limit_name` for `r`'s scene, samples and precision; none when `r` is a
// limit row or not ok.
const Record* limit_row_for(const Record& r, const std::vector<Record>& records,
                            std::string_view limit_name);
// limit_row_for, when that row ran on `r`'s device (same device name): a device's own ceiling
// (a copy, a link, a pass) is no ceiling for a strategy on another device.
const Record* limit_row_on_device(const Record& r, const std::vector<Record>& records,
                                  std::string_view limit_name);
// Whether `limit` wrote under kStoreLimitMinBytes for its request: a pass that small times the
// launch (threads' fork and join, a queue submission), not the memory.
bool limit_too_small(const Record& limit);

// `r`'s points/s over the limit row of `records` for the same scene, samples and precision; none
// when there is no such row, `r` ran on a GPU (device kind other than "cpu": it does not write
// through the host's stores), is a limit row or not ok, or the limit's output is under
// kStoreLimitMinBytes (store_limit_too_small).
std::optional<double> fraction_of_store_limit(const Record& r, const std::vector<Record>& records);
// Whether the limit row for `r`'s request exists but wrote too little to be a bandwidth.
bool store_limit_too_small(const Record& r, const std::vector<Record>& records);

}  // namespace nurbs
