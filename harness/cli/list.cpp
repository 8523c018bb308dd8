#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.h"
#include "harness/store_limit.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs::cli {

namespace {
nlohmann::json capabilities_json(const Capabilities& c) {
  nlohmann::json sampling = nlohmann::json::array();
  if (c.sampling.grid) sampling.push_back("grid");
  if (c.sampling.span_grid) sampling.push_back("span_grid");
  if (c.sampling.explicit_list) sampling.push_back("explicit");
  nlohmann::json precisions = nlohmann::json::array();
  if (c.fp32) precisions.push_back("f32");
  if (c.fp64) precisions.push_back("f64");
  return {{"max_degree", c.max_degree}, {"rational", c.rational},
          {"normals", c.normals},       {"precisions", precisions},
          {"sampling", sampling},       {"updates_control_points", c.updates_control_points}};
}
}  // namespace

int list_command(const ListOptions& options) {
  nlohmann::json strategies = nlohmann::json::array();
  std::string text = "strategies:\n";
  for (const StrategyEntry& e : strategy_registry()) {
    const Availability a = e.probe();
    strategies.push_back({{"name", e.name},
                          {"available", a.available},
                          {"reason", a.reason},
                          {"role", e.role},
                          {"source", e.source},
                          {"capabilities", capabilities_json(e.capabilities())}});
    text += fmt::format("  {:<20} {:<9} {:<40} {}\n", e.name, e.role,
                        a.available ? "available" : "unavailable: " + a.reason, e.source);
  }
  // Not strategies: machine ceilings `run` measures beside them (harness/store_limit.h).
  const std::string limit_description =
      "memory store bandwidth for the request's output (points x bytes per point), same threads";
  text += fmt::format("limits:\n  {:<20} {:<9} {}\n", kStoreLimitName, "limit", limit_description);
  nlohmann::json limits = nlohmann::json::array(
      {{{"name", kStoreLimitName}, {"role", "limit"}, {"description", limit_description}}});
  nlohmann::json scenes = nlohmann::json::array();
  text += "scenes:\n";
  for (const BuiltinSceneInfo& s : builtin_scenes()) {
    scenes.push_back({{"name", s.name}, {"description", s.description}});
    text += fmt::format("  {:<20} {}\n", s.name, s.description);
  }
  if (options.json)
    std::cout << nlohmann::json{{"strategies", strategies}, {"limits", limits}, {"scenes", scenes}}
                     .dump(2)
              << "\n";
  else
    std::cout << text;
  return 0;
}

}  // namespace nurbs::cli
