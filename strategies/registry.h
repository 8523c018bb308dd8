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

const std::vector<StrategyEntry>& strategy_registry();
// nullptr when no strategy has that name.
const StrategyEntry* find_strategy(std::string_view name);
std::vector<std::string> strategy_names();

}  // namespace nurbs
