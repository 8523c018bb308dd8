// Reading a strategy's own options from StrategyOptions.extra, the same way for every strategy.
#pragma once

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <charconv>
#include <stdexcept>
#include <string>
#include <string_view>

#include "strategies/strategy.h"

namespace nurbs {

// extra[key] as an integer >= 1; 0 when absent or empty. Throws std::invalid_argument naming the
// strategy, the option and the value otherwise.
inline int positive_option(const StrategyOptions& options, const std::string& key,
                           std::string_view strategy) {
  const auto it = options.extra.find(key);
  if (it == options.extra.end() || it->second.empty()) return 0;
  int value = 0;
  const auto [end, ec] =
      std::from_chars(it->second.data(), it->second.data() + it->second.size(), value);
  if (ec != std::errc() || end != it->second.data() + it->second.size() || value < 1)
    throw std::invalid_argument(
        fmt::format("{} option {} = '{}': must be a positive integer", strategy, key, it->second));
  return value;
}

// The OpenMP thread count a CPU strategy uses: options.threads, or every core when it is 0.
inline int openmp_threads(const StrategyOptions& options) {
  return options.threads > 0 ? options.threads : std::max(1, omp_get_max_threads());
}

}  // namespace nurbs
