// Phase timing: host wall clock around device-synchronised calls, summarised as min / median /
// max over the repetitions.
#pragma once

#include <chrono>
#include <vector>

namespace nurbs {

struct PhaseStats {
  double min_s = 0, median_s = 0, max_s = 0;
  static PhaseStats of(std::vector<double> seconds);
};

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

template <typename F>
double time_seconds(F&& f) {
  Stopwatch watch;
  f();
  return watch.seconds();
}

// Minor page faults of the whole process so far (every thread: a strategy's OpenMP team faults
// too): a phase that allocates its output afresh each repetition pays one per page it writes,
// which is what made read_back medians many times their minima.
long minor_page_faults();

}  // namespace nurbs
