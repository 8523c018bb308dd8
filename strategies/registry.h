// Every strategy nurbsbench knows, available or not: name, the paper section it implements, an
// availability probe and a factory. The list is explicit (registry.cpp) rather than built by
// static initialisers, which static libraries silently drop.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "strategies/strategy.h"

namespace nurbs {

struct StrategyEntry {
  std::string name;
  std::string source;  // the paper section or library it implements
  std::string role;    // "strategy", "baseline" or "peer"
  std::function<Availability()> probe;
  std::function<Capabilities()> capabilities;
  std::function<std::unique_ptr<Strategy>(const StrategyOptions&)> create;
};

// What a strategy is, whether or not this build can run it: written once in the strategy's folder
// (`<name>_descriptor.cpp`, compiled in every build) and used both by its entry and, in a build
// without its API, by the stub that says why it is unavailable, so `list --json` and the results
// state the same capabilities either way.
struct StrategyDescriptor {
  std::string name;
  std::string source;
  std::string role;
  Capabilities capabilities;
};

// The entry of a strategy this build has: its descriptor, a probe and a factory.
StrategyEntry make_entry(StrategyDescriptor descriptor, std::function<Availability()> probe,
                         std::function<std::unique_ptr<Strategy>(const StrategyOptions&)> create);
// The entry of a strategy this build does not have: never available, for `reason`.
StrategyEntry unavailable_entry(StrategyDescriptor descriptor, std::string reason);
// The entry of a strategy that runs wherever nurbsbench does (the host CPU ones): always
// available, S built from the options when it takes them.
template <class S>
StrategyEntry host_entry(StrategyDescriptor descriptor) {
  return make_entry(
      std::move(descriptor),
      [] {
        return Availability{true, ""};
      },
      [](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
        if constexpr (std::is_constructible_v<S, const StrategyOptions&>)
          return std::make_unique<S>(options);
        else
          return std::make_unique<S>();
      });
}

// Where a strategy added at run time (role "plugin", harness/plugins) came from: the shared
// library's absolute path and the SHA-256 of its bytes (hex), which its records carry.
struct StrategyLibrary {
  std::string path, sha256;
};

// The built-in strategies.
const std::vector<StrategyEntry>& strategy_registry();
// Adds `entry` (`--plugin`) after the built-in ones, kept where the addresses find_strategy hands
// out stay valid as more are added; throws std::invalid_argument when its name is taken.
const StrategyEntry& add_strategy(StrategyEntry entry, StrategyLibrary library);
// The library an added strategy came from; nullptr for a built-in one.
const StrategyLibrary* strategy_library(const StrategyEntry& entry);
// Built-in then added: what `run --strategies all`, `list` and `recommend` go through.
std::vector<const StrategyEntry*> all_strategies();
// nullptr when no strategy (built-in or added) has that name.
const StrategyEntry* find_strategy(std::string_view name);
std::vector<std::string> strategy_names();

}  // namespace nurbs
