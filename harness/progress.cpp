#include "harness/progress.h"

#include <fmt/format.h>

namespace nurbs {

RunProgress::RunProgress(std::ostream& out, std::size_t total, bool terminal,
                         Clock::duration log_interval)
    : out_(out), total_(total), terminal_(terminal), log_interval_(log_interval) {}

std::string RunProgress::duration_text(Clock::duration d) {
  const auto s = std::chrono::duration_cast<std::chrono::seconds>(d).count();
  if (s < 60) return fmt::format("{} s", s);
  if (s < 3600) return fmt::format("{} min {} s", s / 60, s % 60);
  return fmt::format("{} h {} min", s / 3600, s % 3600 / 60);
}

std::string RunProgress::line(std::size_t done, std::size_t total, const std::string& what,
                              Clock::duration elapsed) {
  std::string text = fmt::format("[{}/{}] {}, {}", done + 1, total, what, duration_text(elapsed));
  if (done > 0 && done < total)
    text += fmt::format(", about {} left", duration_text(elapsed / static_cast<long>(done) *
                                                         static_cast<long>(total - done)));
  return text;
}

void RunProgress::start(const std::string& what) {
  const Clock::time_point now = Clock::now();
  const std::string text = line(done_++, total_, what, now - began_);
  if (terminal_) {
    out_ << "\r" << text << "\x1b[K" << std::flush;
  } else if (now - last_log_ >= log_interval_) {
    out_ << text << "\n" << std::flush;
    last_log_ = now;
  }
}

void RunProgress::finish() {
  if (terminal_) out_ << "\r\x1b[K" << std::flush;
}

}  // namespace nurbs
