#include "strategies/registry.h"

#include "strategies/cpu_coxdeboor/cpu_coxdeboor.h"
#include "strategies/cpu_horner/cpu_horner.h"
#include "strategies/cpu_tensor/cpu_tensor.h"
#include "strategies/gl_pingpong/gl_pingpong.h"
#include "strategies/occt/occt_strategy.h"
#include "strategies/sisl/sisl_strategy.h"

namespace nurbs {

const std::vector<StrategyEntry>& strategy_registry() {
  static const std::vector<StrategyEntry> entries = {
      cpu_coxdeboor_entry(), cpu_tensor_entry(),  cpu_horner_entry(),         sisl_entry(),
      occt_entry(),          gl_pingpong_entry(), gl_pingpong_packed_entry(),
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
