// Reading a strategy's own options from StrategyOptions.extra, the same way for every strategy.
#pragma once

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <optional>
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

// What each --strategy-option KEY the built-in strategies read may be, in one table, so the CLI
// refuses a value out of range (exit 2, one line naming the option, the value and the range) before
// any work starts, instead of a strategy failing with it mid-run. The strategies still check what
// they read (a plugin or a test may call them directly); a KEY not listed here is passed on
// unchecked, for plugins, which read any KEY. docs/cli.md lists the same ranges.
struct StrategyOptionRule {
  enum class Kind {
    integer,  // a decimal integer in [low, high]
    number,   // a finite decimal number in [low, high], either end excluded when *_open
    choice,   // one of `choices`, '|'-separated
    numbers   // `count` finite numbers separated by `separator`, each in [low, high]
  };
  std::string_view key;
  Kind kind;
  double low = 0, high = 0;
  bool low_open = false, high_open = false;
  std::string_view choices{};
  int count = 0;
  char separator = ',';
  std::string_view readers{};  // the strategies that read it
};

inline constexpr std::array kStrategyOptionRules = {
    // clang-format off
    StrategyOptionRule{"tile", StrategyOptionRule::Kind::integer, 1, 65536, false, false, {}, 0, ',', "gl-pingpong, glsl-deboor"},
    StrategyOptionRule{"packed", StrategyOptionRule::Kind::choice, 0, 0, false, false, "0|1", 0, ',', "gl-pingpong"},
    StrategyOptionRule{"tspline-points-per-pass", StrategyOptionRule::Kind::integer, 1, 4096, false, false, {}, 0, ',', "gl-tspline"},
    StrategyOptionRule{"trim-resolution", StrategyOptionRule::Kind::integer, 64, 4096, false, false, {}, 0, ',', "gl-pingpong, glsl-deboor"},
    StrategyOptionRule{"trim-tolerance", StrategyOptionRule::Kind::number, 0, 0.1, true, false, {}, 0, ',', "gl-pingpong, glsl-deboor"},
    StrategyOptionRule{"trim-epsilon", StrategyOptionRule::Kind::number, 0, 1, true, true, {}, 0, ',', "cl-stair, vk-ksquad, vk-compute"},
    StrategyOptionRule{"trim-iterations", StrategyOptionRule::Kind::integer, 1, 64, false, false, {}, 0, ',', "cl-stair, vk-ksquad, vk-compute"},
    StrategyOptionRule{"vk-mode", StrategyOptionRule::Kind::choice, 0, 0, false, false, "uniform|adaptive|gs|nonuniform", 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-eq3", StrategyOptionRule::Kind::choice, 0, 0, false, false, "edge|literal", 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-thresholds", StrategyOptionRule::Kind::choice, 0, 0, false, false, "global|surface", 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-corners", StrategyOptionRule::Kind::choice, 0, 0, false, false, "device|host", 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-constants", StrategyOptionRule::Kind::choice, 0, 0, false, false, "device|host", 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-eye", StrategyOptionRule::Kind::numbers, -1e30, 1e30, false, false, {}, 3, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-center", StrategyOptionRule::Kind::numbers, -1e30, 1e30, false, false, {}, 3, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-viewport", StrategyOptionRule::Kind::numbers, 1, 16384, false, false, {}, 2, 'x', "vk-ksquad"},
    StrategyOptionRule{"vk-fov", StrategyOptionRule::Kind::number, 0, 180, true, true, {}, 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-mu", StrategyOptionRule::Kind::number, 0, 1e6, true, false, {}, 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-epsilon", StrategyOptionRule::Kind::number, 0, 1e6, true, false, {}, 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-eta", StrategyOptionRule::Kind::number, 0, 1e6, true, false, {}, 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-max-level", StrategyOptionRule::Kind::integer, 1, 64, false, false, {}, 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-pieces", StrategyOptionRule::Kind::integer, 1, 64, false, false, {}, 0, ',', "vk-ksquad"},
    StrategyOptionRule{"vk-vertices-per-draw", StrategyOptionRule::Kind::integer, 0, 2147483647, false, false, {}, 0, ',', "vk-ksquad, vk-bezier"},
    StrategyOptionRule{"vk-tile-points", StrategyOptionRule::Kind::integer, 16, 65536, false, false, {}, 0, ',', "vk-compute"},
    StrategyOptionRule{"vk-workgroup", StrategyOptionRule::Kind::integer, 1, 1024, false, false, {}, 0, ',', "vk-compute"},
    StrategyOptionRule{"vk-tile-rows", StrategyOptionRule::Kind::integer, 1, 64, false, false, {}, 0, ',', "vk-compute"},
    StrategyOptionRule{"deboor-draw", StrategyOptionRule::Kind::choice, 0, 0, false, false, "per-span|instanced", 0, ',', "glsl-deboor"},
    StrategyOptionRule{"horner-origin", StrategyOptionRule::Kind::choice, 0, 0, false, false, "span|zero", 0, ',', "cpu-horner"},
    StrategyOptionRule{"horner-simd", StrategyOptionRule::Kind::choice, 0, 0, false, false, "auto|explicit", 0, ',', "cpu-horner"},
    StrategyOptionRule{"horner-tables", StrategyOptionRule::Kind::choice, 0, 0, false, false, "horner|forward-differences", 0, ',', "cpu-horner"},
    StrategyOptionRule{"read-back", StrategyOptionRule::Kind::choice, 0, 0, false, false, "staged|mapped", 0, ',', "the OpenCL strategies"},
    StrategyOptionRule{"simd", StrategyOptionRule::Kind::choice, 0, 0, false, false, "on|off", 0, ',', "cpu-tensor"},
    StrategyOptionRule{"stores", StrategyOptionRule::Kind::choice, 0, 0, false, false, "cached|streaming", 0, ',', "cpu-tensor"},
    StrategyOptionRule{"device", StrategyOptionRule::Kind::integer, 0, 1023, false, false, {}, 0, ',', "the OpenCL and Vulkan strategies (--device)"},
    StrategyOptionRule{"gl", StrategyOptionRule::Kind::choice, 0, 0, false, false, "egl|osmesa", 0, ',', "the GL strategies (--gl)"},
    // clang-format on
};

// The range of `rule` in words: "an integer in 64..4096", "a number in (0, 0.1]", "one of a, b",
// "3 numbers separated by ',', each in [-1e+30, 1e+30]".
inline std::string strategy_option_range(const StrategyOptionRule& rule) {
  switch (rule.kind) {
    case StrategyOptionRule::Kind::integer:
      return fmt::format("an integer in {:.0f}..{:.0f}", rule.low, rule.high);
    case StrategyOptionRule::Kind::number:
      return fmt::format("a number in {}{:g}, {:g}{}", rule.low_open ? '(' : '[', rule.low,
                         rule.high, rule.high_open ? ')' : ']');
    case StrategyOptionRule::Kind::choice: {
      std::string words(rule.choices);
      std::string out;
      for (const char c : words) out += c == '|' ? std::string(", ") : std::string(1, c);
      return "one of " + out;
    }
    case StrategyOptionRule::Kind::numbers:
      return fmt::format("{} numbers separated by '{}', each in [{:g}, {:g}]", rule.count,
                         rule.separator, rule.low, rule.high);
  }
  return {};
}

// Why `value` is not a value of `key` ("trim-resolution must be an integer in 64..4096
// (gl-pingpong, glsl-deboor)"); nullopt when it is, when it is empty (the strategy's default) or
// when no built-in strategy reads `key`.
inline std::optional<std::string> strategy_option_problem(std::string_view key,
                                                          std::string_view value) {
  const auto rule = std::find_if(kStrategyOptionRules.begin(), kStrategyOptionRules.end(),
                                 [&](const StrategyOptionRule& r) { return r.key == key; });
  if (rule == kStrategyOptionRules.end() || value.empty()) return std::nullopt;
  const auto number_in_range = [&](std::string_view text, bool whole) {
    double x = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(x))
      return false;
    if (whole && x != std::floor(x)) return false;
    // !(a < b) rather than a >= b: NaN never passes (it cannot reach here, but the habit holds).
    if (rule->low_open ? !(x > rule->low) : !(x >= rule->low)) return false;
    return rule->high_open ? x < rule->high : x <= rule->high;
  };
  bool ok = false;
  switch (rule->kind) {
    case StrategyOptionRule::Kind::integer:
      ok = value.find_first_not_of("0123456789") == std::string_view::npos &&
           number_in_range(value, true);
      break;
    case StrategyOptionRule::Kind::number:
      ok = number_in_range(value, false);
      break;
    case StrategyOptionRule::Kind::choice: {
      std::string_view rest = rule->choices;
      while (!ok && !rest.empty()) {
        const std::size_t bar = std::min(rest.find('|'), rest.size());
        ok = rest.substr(0, bar) == value;
        rest.remove_prefix(std::min(bar + 1, rest.size()));
      }
      break;
    }
    case StrategyOptionRule::Kind::numbers: {
      int count = 0;
      ok = true;
      std::string_view rest = value;
      for (;;) {
        const std::size_t cut = std::min(rest.find(rule->separator), rest.size());
        ok = ok && number_in_range(rest.substr(0, cut), false);
        ++count;
        if (cut == rest.size()) break;
        rest.remove_prefix(cut + 1);
      }
      ok = ok && count == rule->count;
      break;
    }
  }
  if (ok) return std::nullopt;
  return fmt::format("{} must be {} ({})", key, strategy_option_range(*rule), rule->readers);
}

// The OpenMP thread count a CPU strategy uses: options.threads, or every core when it is 0.
inline int openmp_threads(const StrategyOptions& options) {
  return options.threads > 0 ? options.threads : std::max(1, omp_get_max_threads());
}

}  // namespace nurbs
