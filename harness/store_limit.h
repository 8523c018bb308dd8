// The memory-write ceiling a grid evaluator's output stream runs into, measured in the same run
// as the strategies (issue 6: "cpu-tensor f32 >= 50% of the machine's memory write bandwidth").
// Every thread (the run's one thread setting) stores into its own share of a buffer the size of
// the request's result: points x (3, or 6 with normals) x the precision's scalar size. The record
// it yields is a row like a strategy's, of role "limit": its throughput is the points per second
// a strategy would reach if writing its results were all it did; it evaluates nothing and has no
// accuracy.
#pragma once

#include <cstddef>
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

// Seconds to store `values` scalars of `scalar_bytes` each (4 or 8) into `buffer`, every thread
// its own contiguous share; `pass` changes the stored value so no pass can be elided.
double time_store_pass(void* buffer, std::size_t values, std::size_t scalar_bytes, int pass);

// Bytes a strategy writes per sample for `request` (positions, plus normals when asked).
std::size_t result_bytes_per_point(const EvalRequest& request);

// The limit row for `scene` and `request`: `repetitions` store passes after a first-touch pass and
// a warm-up pass, both untimed.
Record measure_store_limit(const Scene& scene, const EvalRequest& request, int repetitions);

// `r`'s points/s over the limit row of `records` for the same scene, samples and precision; none
// when there is no such row, `r` is a limit row or not ok, or the limit's output is under
// kStoreLimitMinBytes (store_limit_too_small).
std::optional<double> fraction_of_store_limit(const Record& r, const std::vector<Record>& records);
// Whether the limit row for `r`'s request exists but wrote too little to be a bandwidth.
bool store_limit_too_small(const Record& r, const std::vector<Record>& records);

}  // namespace nurbs
