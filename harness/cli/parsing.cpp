#include "harness/cli/parsing.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <set>
#include <string>
#include <thread>

#include "harness/metrics.h"
#include "reference/error_text.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"
#include "strategies/strategy_options.h"

namespace nurbs::cli {

std::string_view trim_blanks(std::string_view text) {
  const std::size_t first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

namespace {

// "OPTION = 'TEXT'": how every error below starts (the value escaped and cut, docs/design.md §The
// CLI: one line).
std::string option_text(std::string_view option, std::string_view text) {
  return fmt::format("{} = '{}'", option, printable(text, kQuotedValueBytes));
}

int parse_int(std::string_view option, std::string_view whole, std::string_view digits, int lo,
              int hi) {
  int value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (digits.empty() || error != std::errc() || end != digits.data() + digits.size() ||
      value < lo || value > hi)
    throw InputError(fmt::format("{}: '{}' must be an integer in {}..{}",
                                 option_text(option, whole), printable(digits, kQuotedValueBytes),
                                 lo, hi));
  return value;
}

// A sampling given twice would be measured twice and reported as two rows of one measurement.
void refuse_repeats(std::string_view option, std::string_view text,
                    const std::vector<Sampling>& samplings) {
  std::set<std::string> seen;
  for (const Sampling& s : samplings)
    if (!seen.insert(s.label()).second)
      throw InputError(fmt::format("{}: {} is given twice", option_text(option, text), s.label()));
}

}  // namespace

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

std::vector<std::string> parse_list(std::string_view option, std::string_view text) {
  std::vector<std::string> out;
  if (trim_blanks(text).empty()) return out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    const std::string_view item = trim_blanks(text.substr(
        start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
    if (item.empty())
      throw InputError(fmt::format("{}: item {} is empty (items are separated by single commas)",
                                   option_text(option, text), out.size() + 1));
    if (out.size() == kMaxListItems)
      throw InputError(
          fmt::format("{}: more than {} items", option_text(option, text), kMaxListItems));
    out.emplace_back(item);
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<std::string> scene_list(std::string_view text, std::string_view option) {
  if (text == "default" || text == "all") {
    std::vector<std::string> names;
    for (const BuiltinSceneInfo& s : builtin_scenes())
      // The largest of the numbered families cost minutes at the accuracy run's grids and show
      // nothing their smaller listed sizes do not: "all" only.
      if (text == "all" || (s.name != "many-4096" && s.name != "many-ducks-64"))
        names.push_back(s.name);
    return names;
  }
  std::vector<std::string> names = parse_list(option, text);
  std::set<std::string_view> seen;
  for (const std::string& name : names)
    if (!seen.insert(name).second)
      throw InputError(fmt::format("{}: '{}' is given twice", option_text(option, text),
                                   printable(name, kQuotedValueBytes)));
  return names;
}

std::vector<Sampling> parse_grid_list(std::string_view option, std::string_view text) {
  std::vector<Sampling> out;
  for (const std::string& item : parse_list(option, text)) {
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
    throw InputError(
        fmt::format("{}: give at least one grid such as 64x64", option_text(option, text)));
  refuse_repeats(option, text, out);
  return out;
}

std::vector<Sampling> parse_span_list(std::string_view option, std::string_view text) {
  std::vector<Sampling> out;
  for (const std::string& item : parse_list(option, text)) {
    Sampling s;
    s.mode = SamplingMode::span_grid;
    s.span_steps = parse_int(option, item, item, 1, kMaxSpanSteps);
    out.push_back(s);
  }
  if (out.empty())
    throw InputError(
        fmt::format("{}: give at least one step count such as 4", option_text(option, text)));
  refuse_repeats(option, text, out);
  return out;
}

Precision parse_precision(std::string_view text) {
  if (text == "f32") return Precision::f32;
  if (text == "f64") return Precision::f64;
  throw InputError(fmt::format("{}: must be f32 or f64", option_text("--precision", text)));
}

ReferencePrecision parse_reference(std::string_view text) {
  ReferencePrecision precision;
  if (!parse_reference_precision(text, precision))
    throw InputError(fmt::format("{}: must be long-double or float128{}",
                                 option_text("--reference", text),
                                 NURBSBENCH_HAS_FLOAT128 ? "" : " (this build has no __float128)"));
  return precision;
}

double parse_trim_band(const std::optional<std::string>& text) {
  if (!text) return kDefaultTrimBand;
  // from_chars, not strtod: no locale, no hex floats, no blanks around the number.
  double band = 0;
  const auto [end, error] = std::from_chars(text->data(), text->data() + text->size(), band);
  if (text->empty() || error != std::errc() || end != text->data() + text->size() ||
      !std::isfinite(band) || band < 0 || band >= 1)
    throw InputError(fmt::format(
        "{}: must be a number in [0, 1) (a fraction of each trimmed surface's (u, v) domain "
        "diagonal; default {:g})",
        option_text("--trim-band", *text), kDefaultTrimBand));
  return band + 0.0;  // -0 is 0
}

std::map<std::string, std::string> backend_extra(const std::string& gl, const std::string& device,
                                                 const std::vector<std::string>& strategy_options) {
  std::map<std::string, std::string> extra;
  for (const std::string& option : strategy_options) {
    const std::size_t eq = option.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError(fmt::format("{}: must be KEY=VALUE (e.g. vk-mode=adaptive)",
                                   option_text("--strategy-option", option)));
    // The second value would silently win over the first.
    if (!extra.emplace(option.substr(0, eq), option.substr(eq + 1)).second)
      throw InputError(fmt::format("{}: {} is given twice",
                                   option_text("--strategy-option", option),
                                   printable(option.substr(0, eq), kQuotedValueBytes)));
    // Before any work: a value out of range is the command line's mistake, not a strategy's
    // failure halfway through a run.
    if (const auto problem = strategy_option_problem(option.substr(0, eq), option.substr(eq + 1)))
      throw InputError(fmt::format("{}: {}", option_text("--strategy-option", option), *problem));
  }
  if (!gl.empty()) extra["gl"] = gl;
  if (!device.empty()) {
    parse_int("--device", device, device, 0, 1023);
    extra["device"] = device;
  }
  return extra;
}

std::string writable_output_file(std::string_view option, const std::string& path) {
  namespace fs = std::filesystem;
  const auto refuse = [&](std::string_view why) {
    throw InputError(fmt::format("{}: {}", option_text(option, path), why));
  };
  if (path.empty()) refuse("the file name is empty");
  std::error_code ec;
  const fs::path absolute = fs::absolute(path, ec);
  if (ec) refuse(ec.message());
  if (fs::is_directory(absolute, ec)) refuse("is a directory");
  const fs::path folder = absolute.parent_path();
  if (!fs::is_directory(folder, ec))
    refuse(fmt::format("its folder {} does not exist", printable(folder.string(), 256)));
  std::string probe = (folder / ".nurbsbench-write-check-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0)
    refuse(fmt::format("cannot create a file in {}: {}", printable(folder.string(), 256),
                       std::strerror(errno)));
  ::close(fd);
  ::unlink(probe.c_str());
  return absolute.string();
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
