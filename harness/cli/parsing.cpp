#include <fmt/format.h>
#include <omp.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>
#include <thread>

#include "harness/cli/commands.h"
#include "harness/metrics.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"

namespace nurbs::cli {

std::vector<std::string> split_list(std::string_view text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = text.find(',', start);
    const std::string_view item = text.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    if (!item.empty()) out.emplace_back(item);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<std::string> scene_list(const std::string& text) {
  if (text == "default" || text == "all") {
    std::vector<std::string> names;
    for (const BuiltinSceneInfo& s : builtin_scenes())
      if (text == "all" || s.name != "many-4096") names.push_back(s.name);
    return names;
  }
  return split_list(text);
}

namespace {

int parse_int(std::string_view option, std::string_view whole, std::string_view digits, int lo,
              int hi) {
  int value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() ||
      value < lo || value > hi)
    throw InputError(
        fmt::format("{} = '{}': '{}' must be an integer in {}..{}", option, whole, digits, lo, hi));
  return value;
}

}  // namespace

std::vector<Sampling> parse_grid_list(std::string_view option, std::string_view text) {
  std::vector<Sampling> out;
  for (const std::string& item : split_list(text)) {
    const std::size_t x = item.find('x');
    Sampling s;
    s.mode = SamplingMode::grid;
    s.grid_u =
        parse_int(option, item, std::string_view(item).substr(0, x), 2, kMaxGridPerDirection);
    s.grid_v = x == std::string::npos
                   ? s.grid_u
                   : parse_int(option, item, std::string_view(item).substr(x + 1), 2,
                               kMaxGridPerDirection);
    out.push_back(s);
  }
  if (out.empty())
    throw InputError(fmt::format("{} = '{}': give at least one grid such as 64x64", option, text));
  return out;
}

std::vector<Sampling> parse_span_list(std::string_view option, std::string_view text) {
  std::vector<Sampling> out;
  for (const std::string& item : split_list(text)) {
    Sampling s;
    s.mode = SamplingMode::span_grid;
    s.span_steps = parse_int(option, item, item, 1, kMaxSpanSteps);
    out.push_back(s);
  }
  if (out.empty())
    throw InputError(
        fmt::format("{} = '{}': give at least one step count such as 4", option, text));
  return out;
}

Precision parse_precision(std::string_view text) {
  if (text == "f32") return Precision::f32;
  if (text == "f64") return Precision::f64;
  throw InputError(fmt::format("--precision = '{}': must be f32 or f64", text));
}

ReferencePrecision parse_reference(std::string_view text) {
  ReferencePrecision precision;
  if (!parse_reference_precision(text, precision))
    throw InputError(fmt::format("--reference = '{}': must be long-double or float128{}", text,
                                 NURBSBENCH_HAS_FLOAT128 ? "" : " (this build has no __float128)"));
  return precision;
}

double parse_trim_band(const std::optional<std::string>& text) {
  if (!text) return kDefaultTrimBand;
  char* end = nullptr;
  const double band = std::strtod(text->c_str(), &end);
  if (text->empty() || end != text->c_str() + text->size() || !std::isfinite(band) || band < 0 ||
      band >= 1)
    throw InputError(fmt::format(
        "--trim-band = '{}': must be a number in [0, 1) (a fraction of each trimmed surface's "
        "(u, v) domain diagonal; default {:g})",
        *text, kDefaultTrimBand));
  return band;
}

std::map<std::string, std::string> backend_extra(const std::string& gl, const std::string& device,
                                                 const std::vector<std::string>& strategy_options) {
  std::map<std::string, std::string> extra;
  for (const std::string& option : strategy_options) {
    const std::size_t eq = option.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError(fmt::format(
          "--strategy-option = '{}': must be KEY=VALUE (e.g. vk-mode=adaptive)", option));
    extra[option.substr(0, eq)] = option.substr(eq + 1);
  }
  if (!gl.empty()) extra["gl"] = gl;
  if (!device.empty()) {
    parse_int("--device", device, device, 0, 1023);
    extra["device"] = device;
  }
  return extra;
}

int apply_thread_setting(int threads) {
  if (threads < 0 || threads > 4096)
    throw InputError(fmt::format("--threads = {}: must be in 0..4096 (0: every core)", threads));
  const int count =
      threads > 0 ? threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  // One setting for every backend: OpenMP (CPU strategies, reference), Mesa llvmpipe/lavapipe,
  // PoCL. Set before any context is created.
  const std::string text = std::to_string(count);
  ::setenv("OMP_NUM_THREADS", text.c_str(), 1);
  ::setenv("LP_NUM_THREADS", text.c_str(), 1);
  ::setenv("POCL_MAX_PTHREAD_COUNT", text.c_str(), 1);
  omp_set_num_threads(count);
  return count;
}

}  // namespace nurbs::cli
