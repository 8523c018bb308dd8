// nlohmann-json's exception text without its "[json.exception.parse_error.101] " prefix, with
// control bytes (a binary file's content quoted back) escaped so an error stays one clean line.
#pragma once

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <string>

namespace nurbs {

inline std::string json_error_text(const nlohmann::json::exception& e) {
  std::string message = e.what();
  if (message.starts_with("[json.exception.")) {
    if (auto pos = message.find("] "); pos != std::string::npos) message = message.substr(pos + 2);
  }
  std::string clean;
  for (unsigned char c : message)
    clean += (c < 0x20 || c == 0x7f) ? fmt::format("\\x{:02x}", c)
                                     : std::string(1, static_cast<char>(c));
  return clean;
}

}  // namespace nurbs
