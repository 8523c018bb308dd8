// The CLI's value parsers (harness/cli/parsing.h). The first byte picks the parser (mod 7), the
// rest is the option's text. What a parser accepts is checked against its contract (bounds, no
// repeats, no empty items, labels that parse back to the same samplings); what it refuses must be
// InputError with one line naming the option.
#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "fuzz_check.h"
#include "harness/cli/parsing.h"

namespace nurbs::fuzz {
namespace {

using namespace nurbs::cli;

void check_samplings(std::string_view option, const std::vector<Sampling>& list,
                     SamplingMode mode) {
  check(!list.empty() && list.size() <= kMaxListItems, "list size out of bounds");
  std::set<std::string> labels;
  std::vector<std::string> items;
  for (const Sampling& s : list) {
    check(s.mode == mode, "wrong sampling mode");
    if (mode == SamplingMode::grid) {
      check(s.grid_u >= 2 && s.grid_u <= kMaxGridPerDirection && s.grid_v >= 2 &&
                s.grid_v <= kMaxGridPerDirection,
            "grid side out of bounds", s.label());
      items.push_back(s.label());
    } else {
      check(s.span_steps >= 1 && s.span_steps <= kMaxSpanSteps, "span steps out of bounds",
            s.label());
      items.push_back(std::to_string(s.span_steps));
    }
    check(labels.insert(s.label()).second, "a sampling accepted twice", s.label());
  }
  // The canonical spelling reads back to the same list.
  const std::string canonical = fmt::format("{}", fmt::join(items, ","));
  const std::vector<Sampling> again = mode == SamplingMode::grid
                                          ? parse_grid_list(option, canonical)
                                          : parse_span_list(option, canonical);
  check(again.size() == list.size(), "canonical list reads back to another size", canonical);
  for (std::size_t k = 0; k < list.size(); ++k)
    check(again[k].label() == list[k].label(), "canonical list reads back differently", canonical);
}

void check_items(const std::vector<std::string>& items) {
  check(items.size() <= kMaxListItems, "list size out of bounds");
  std::set<std::string> seen;
  for (const std::string& item : items) {
    check(!item.empty() && trim_blanks(item) == item, "empty or untrimmed item", item);
    check(item.find(',') == std::string::npos, "item holds a comma", item);
    check(seen.insert(item).second, "an item accepted twice", item);
  }
}

std::vector<std::string> lines_of(std::string_view text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    lines.emplace_back(text.substr(start, end - start));
    start = end + 1;
  }
  return lines;
}

constexpr int kParsers = 7;

void run(std::uint8_t selector, std::string_view text) {
  switch (selector % kParsers) {
    case 0:
      check_samplings("--samples", parse_grid_list("--samples", text), SamplingMode::grid);
      break;
    case 1:
      check_samplings("--span-samples", parse_span_list("--span-samples", text),
                      SamplingMode::span_grid);
      break;
    case 2:
      if (text != "default" && text != "all") check_items(scene_list(text));
      break;
    case 3:
      check(parse_precision(text) == (text == "f32" ? Precision::f32 : Precision::f64),
            "precision misread", text);
      break;
    case 4:
      parse_reference(text);
      check(text == "long-double" || text == "float128", "unknown reference accepted", text);
      break;
    case 6: {
      const double band = parse_trim_band(std::string(text));
      check(std::isfinite(band) && band >= 0 && band < 1 && !std::signbit(band),
            "trim band out of [0, 1)", text);
      check(parse_trim_band(fmt::format("{}", band)) == band, "trim band reads back differently",
            text);
      break;
    }
    case 5: {
      const std::vector<std::string> options = lines_of(text);
      const auto extra = backend_extra("", "", options);
      check(extra.size() == options.size(), "a strategy option lost");
      for (const auto& [key, value] : extra) check(!key.empty(), "empty option key");
      break;
    }
  }
}

constexpr const char* kOptions[] = {"--samples",   "--span-samples",    "--scenes",   "--precision",
                                    "--reference", "--strategy-option", "--trim-band"};

}  // namespace
}  // namespace nurbs::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace nurbs;
  if (size == 0) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
  try {
    fuzz::run(data[0], text);
  } catch (const InputError& e) {
    fuzz::check_error_line(e, fuzz::kOptions[data[0] % fuzz::kParsers]);
  }
  return 0;
}
