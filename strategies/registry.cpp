#include "strategies/registry.h"

#include "strategies/cpu_coxdeboor/cpu_coxdeboor.h"

namespace nurbs {

const std::vector<StrategyEntry>& strategy_registry() {
  static const std::vector<StrategyEntry> entries = {
      cpu_coxdeboor_entry(),
  };
  return entries;
}

const StrategyEntry* find_strategy(std::string_view name) {
  for (const StrategyEntry& e : strategy_registry())
    if (e.name == name) return &e;
  return nullptr;
}

std::vector<std::string> strategy_names() {
  std::vector<std::string> names;
  for (const StrategyEntry& e : strategy_registry()) names.push_back(e.name);
  return names;
}

}  // namespace nurbs
