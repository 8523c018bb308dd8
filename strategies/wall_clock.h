// Seconds of host wall clock around a call: what the limit rows' benches time (a copy's submission
// and its bounded wait), as the harness times a strategy's phases (harness/timing.h, which the
// strategies do not include).
#pragma once

#include <chrono>
#include <utility>

namespace nurbs {

template <typename F>
double wall_seconds(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  std::forward<F>(f)();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace nurbs
