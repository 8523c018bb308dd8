// The line `run` shows while it works: measurements done of the total, what runs now, the time
// spent and an estimate of the time left. A terminal gets one line redrawn in place; a log (a pipe,
// a file, CI) gets a plain line at most every `log_interval`, so short runs print nothing and long
// ones are not silent.
#pragma once

#include <chrono>
#include <cstddef>
#include <ostream>
#include <string>

namespace nurbs {

class RunProgress {
 public:
  using Clock = std::chrono::steady_clock;

  RunProgress(std::ostream& out, std::size_t total, bool terminal,
              Clock::duration log_interval = std::chrono::seconds(10));
  // Announces the measurement about to run ("cpu-tensor on patch144 (1024x1024)").
  void start(const std::string& what);
  // Clears the terminal line (nothing to do for a log).
  void finish();

  // "[12/40] cpu-tensor on patch144 (64x64), 1 min 5 s, about 2 min 10 s left": the estimate is
  // the mean time per measurement so far times those left, absent before the first one ends.
  static std::string line(std::size_t done, std::size_t total, const std::string& what,
                          Clock::duration elapsed);
  // "45 s", "2 min 5 s", "1 h 3 min".
  static std::string duration_text(Clock::duration d);

 private:
  std::ostream& out_;
  std::size_t total_;
  std::size_t done_ = 0;
  bool terminal_;
  Clock::duration log_interval_;
  Clock::time_point began_ = Clock::now();
  Clock::time_point last_log_ = began_;
};

}  // namespace nurbs
