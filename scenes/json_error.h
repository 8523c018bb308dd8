// nlohmann-json's exception text without its "[json.exception.parse_error.101] " prefix, with
// control bytes (a binary file's content quoted back) escaped so an error stays one clean line.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "reference/error_text.h"

namespace nurbs {

inline std::string json_error_text(const nlohmann::json::exception& e) {
  std::string message = e.what();
  if (message.starts_with("[json.exception.")) {
    if (auto pos = message.find("] "); pos != std::string::npos) message = message.substr(pos + 2);
  }
  return printable(message);
}

}  // namespace nurbs
