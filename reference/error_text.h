// Text quoted back in an error message (a file's line, an option's value, a JSON parser's
// excerpt): control bytes escaped as \xNN so the error stays one clean line whatever the input
// held (NUL, CR, a binary file), and cut so a giant input is not printed whole.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <string>
#include <string_view>

namespace nurbs {

// A byte that must not reach an error line raw (C0 controls and DEL).
inline constexpr bool is_control_byte(unsigned char c) {
  return c < 0x20 || c == 0x7f;
}

// At most `max_bytes` of `text` (cut back to a UTF-8 character boundary, "..." appended).
inline std::string printable(std::string_view text,
                             std::size_t max_bytes = std::string_view::npos) {
  std::size_t keep = std::min(text.size(), max_bytes);
  if (keep < text.size())
    while (keep > 0 && (static_cast<unsigned char>(text[keep]) & 0xc0) == 0x80) --keep;
  std::string out;
  out.reserve(keep);
  for (const unsigned char c : text.substr(0, keep))
    if (is_control_byte(c))
      out += fmt::format("\\x{:02x}", c);
    else
      out += static_cast<char>(c);
  if (keep < text.size()) out += "...";
  return out;
}

// The length error messages quote a value to: the whole of any sane value, a prefix of a wild one.
inline constexpr std::size_t kQuotedValueBytes = 64;

}  // namespace nurbs
