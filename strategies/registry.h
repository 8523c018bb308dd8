// Every strategy nurbsbench knows, available or not: name, the paper section it implements, an
// availability probe and a factory. The list is explicit (registry.cpp) rather than built by
// static initialisers, which static libraries silently drop.
#pragma once

#include <functional>
#include <memory>
#include <string>
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
