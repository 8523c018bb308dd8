// Every --strategy-option a built-in strategy reads has a range (strategies/strategy_options.h,
// kStrategyOptionRules): a value below it, above it or not a number is bad input -- exit 2, one
// line naming the option, the value and the range, before any work -- through `run` and `eval`
// alike, and docs/cli.md states the same ranges.
#include "strategies/strategy_options.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "harness/cli/parsing.h"
#include "reference/validation.h"
#include "run_cli.h"

namespace nurbs::test {
namespace {

using Kind = StrategyOptionRule::Kind;

std::string number_text(double x, bool whole) {
  return whole ? fmt::format("{:.0f}", x) : fmt::format("{:g}", x);
}

// Values of `rule` just outside its range, and ones that are not numbers (or not a choice).
std::vector<std::string> bad_values(const StrategyOptionRule& rule) {
  const bool whole = rule.kind == Kind::integer;
  const double step = whole ? 1 : std::max(1.0, std::abs(rule.high));
  const std::string below = number_text(rule.low_open ? rule.low : rule.low - step, whole);
  const std::string above = number_text(rule.high_open ? rule.high : rule.high + step, whole);
  switch (rule.kind) {
    case Kind::integer:
      return {below, above, "x", "1.5"};
    case Kind::number:
      return {below, above, "x", "nan"};
    case Kind::choice:
      return {"not-a-choice", "x"};
    case Kind::numbers: {
      std::string too_few = below, out_of_range = above;
      for (int k = 1; k < rule.count; ++k) out_of_range += rule.separator + above;
      return {too_few, out_of_range, "x"};
    }
  }
  return {};
}

// Values at the ends of the range (or every choice), all accepted.
std::vector<std::string> good_values(const StrategyOptionRule& rule) {
  const bool whole = rule.kind == Kind::integer;
  if (rule.kind == Kind::choice) {
    std::vector<std::string> all;
    std::string_view rest = rule.choices;
    while (!rest.empty()) {
      const std::size_t bar = std::min(rest.find('|'), rest.size());
      all.emplace_back(rest.substr(0, bar));
      rest.remove_prefix(std::min(bar + 1, rest.size()));
    }
    return all;
  }
  // An open end is approached, not reached.
  const double low = rule.low_open ? rule.low + (rule.high - rule.low) * 1e-3 : rule.low;
  const double high = rule.high_open ? rule.high - (rule.high - rule.low) * 1e-3 : rule.high;
  std::vector<std::string> values = {number_text(low, whole), number_text(high, whole)};
  if (rule.kind == Kind::numbers)
    for (std::string& v : values) {
      const std::string one = v;
      for (int k = 1; k < rule.count; ++k) v += rule.separator + one;
    }
  return values;
}

TEST(StrategyOptions, EveryRangeIsCheckedByTheParser) {
  for (const StrategyOptionRule& rule : kStrategyOptionRules) {
    for (const std::string& value : good_values(rule))
      EXPECT_NO_THROW(cli::backend_extra("", "", {std::string(rule.key) + "=" + value}))
          << rule.key << "=" << value;
    for (const std::string& value : bad_values(rule)) {
      try {
        cli::backend_extra("", "", {std::string(rule.key) + "=" + value});
        ADD_FAILURE() << rule.key << "=" << value << " accepted";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(strategy_option_range(rule)), std::string::npos)
            << e.what();
      }
    }
  }
  // Keys no built-in strategy reads are a plugin's: passed on as given.
  EXPECT_NO_THROW(cli::backend_extra("", "", {"my-plugin-knob=anything at all"}));
}

// Through the CLI: each rule's bad values alternate between run and eval, so every rule meets both
// verbs and every bad value one of them, each refused before any output is touched.
TEST(StrategyOptions, OutOfRangeValuesAreExitTwoThroughRunAndEval) {
  TempDir tmp;
  int k = 0;
  for (const StrategyOptionRule& rule : kStrategyOptionRules)
    for (const std::string& value : bad_values(rule)) {
      const std::string option = std::string(rule.key) + "=" + value;
      const bool run = ++k % 2 == 0;
      const CliResult r =
          run ? run_cli({"run", "--strategies", "cpu-coxdeboor", "--scenes", "patch144",
                         "--strategy-option", option, "--out", tmp / "never"})
              : run_cli({"eval", "--strategy", "cpu-coxdeboor", "--scene", "patch144",
                         "--strategy-option", option, "--out", tmp / "never.csv"});
      EXPECT_EQ(r.exit_code, 2) << (run ? "run " : "eval ") << option << ": " << r.err;
      EXPECT_TRUE(is_one_error_line(r.err)) << r.err;
      EXPECT_NE(r.err.find(fmt::format("--strategy-option = '{}': {} must be {}", option, rule.key,
                                       strategy_option_range(rule))),
                std::string::npos)
          << r.err;
    }
  EXPECT_FALSE(std::filesystem::exists(tmp / "never"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "never.csv"));
}

TEST(StrategyOptions, DocsStateEveryRange) {
  const std::string docs = read_text(std::string(NURBSBENCH_SOURCE_DIR) + "/docs/cli.md");
  for (const StrategyOptionRule& rule : kStrategyOptionRules)
    EXPECT_NE(docs.find(fmt::format("| `{}` | {} |", rule.key, strategy_option_range(rule))),
              std::string::npos)
        << "docs/cli.md has no row for " << rule.key << ": | `" << rule.key << "` | "
        << strategy_option_range(rule) << " | " << rule.readers << " |";
}

}  // namespace
}  // namespace nurbs::test
