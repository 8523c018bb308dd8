// What every fuzz target asserts about a parser: it returns a valid result or throws InputError
// whose message is the CLI's one clean line naming where; anything else (another exception type,
// a crash, a sanitizer report, a failed check here) is a finding. A failed check aborts, which
// libFuzzer records as a crash with its input; the replay test (replay_main.cpp) fails on it too.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "reference/error_text.h"
#include "reference/validation.h"

namespace nurbs::fuzz {

[[noreturn]] inline void finding(std::string_view what, std::string_view detail = {}) {
  std::fprintf(stderr, "fuzz finding: %.*s%s%.*s\n", static_cast<int>(what.size()), what.data(),
               detail.empty() ? "" : ": ", static_cast<int>(detail.size()), detail.data());
  std::abort();
}

inline void check(bool ok, std::string_view what, std::string_view detail = {}) {
  if (!ok) finding(what, detail);
}

// docs/design.md §The CLI: one line, naming the file or option first; no control byte of the input
// quoted raw.
inline void check_error_line(const InputError& e, std::string_view origin) {
  const std::string_view message = e.what();
  check(message.starts_with(origin), "error does not start with its origin", message);
  for (const unsigned char c : message)
    check(!is_control_byte(c), "error message holds a control byte (not one clean line)", message);
}

}  // namespace nurbs::fuzz
