// The memory-write ceiling a grid evaluator's output stream runs into, measured in the same run
// as the strategies (issue 6: "cpu-tensor f32 >= 50% of the machine's memory write bandwidth").
// Every thread (the run's one thread setting) stores into its own share of a buffer the size of
// the request's result: points x (3, or 6 with normals) x the precision's scalar size. The record
// it yields is a row like a strategy's, of role "limit": its throughput is the points per second
// a strategy would reach if writing its results were all it did; it evaluates nothing and has no
// accuracy.
#pragma once

#include <cstddef>
#include <string_view>

#include "harness/record.h"
#include "reference/surface.h"
#include "strategies/strategy.h"

namespace nurbs {

inline constexpr std::string_view kStoreLimitName = "limit-store-bandwidth";

// Seconds to store `values` scalars of `scalar_bytes` each (4 or 8) into `buffer`, every thread
// its own contiguous share; `pass` changes the stored value so no pass can be elided.
double time_store_pass(void* buffer, std::size_t values, std::size_t scalar_bytes, int pass);

// Bytes a strategy writes per sample for `request` (positions, plus normals when asked).
std::size_t result_bytes_per_point(const EvalRequest& request);

// The limit row for `scene` and `request`: `repetitions` store passes after a warm-up.
Record measure_store_limit(const Scene& scene, const EvalRequest& request, int repetitions);

}  // namespace nurbs
