#include "strategies/registry.h"

#include <fmt/format.h>

#include <deque>
#include <stdexcept>

#include "strategies/cl_stair/cl_stair.h"
#include "strategies/cl_tspline_bezier/cl_tspline_bezier.h"
#include "strategies/cpu_bezier/cpu_bezier.h"
#include "strategies/cpu_coxdeboor/cpu_coxdeboor.h"
#include "strategies/cpu_horner/cpu_horner.h"
#include "strategies/cpu_tensor/cpu_tensor.h"
#include "strategies/cpu_tspline/cpu_tspline.h"
#include "strategies/cpu_tspline_bezier/cpu_tspline_bezier.h"
#include "strategies/gl_pingpong/gl_pingpong.h"
#include "strategies/gl_tspline/gl_tspline.h"
#include "strategies/glsl_deboor/glsl_deboor.h"
#include "strategies/glu_nurbs/glu_nurbs.h"
#include "strategies/occt/occt_strategy.h"
#include "strategies/sisl/sisl_strategy.h"
#include "strategies/vk_bezier/vk_bezier.h"
#include "strategies/vk_compute/vk_compute.h"
#include "strategies/vk_ksquad/vk_ksquad.h"

namespace nurbs {

StrategyEntry make_entry(StrategyDescriptor descriptor, std::function<Availability()> probe,
                         std::function<std::unique_ptr<Strategy>(const StrategyOptions&)> create) {
  return {std::move(descriptor.name),
          std::move(descriptor.source),
          std::move(descriptor.role),
          std::move(probe),
          [capabilities = descriptor.capabilities] { return capabilities; },
          std::move(create)};
}

StrategyEntry unavailable_entry(StrategyDescriptor descriptor, std::string reason) {
  return make_entry(
      std::move(descriptor),
      [reason] {
        return Availability{false, reason};
      },
      [reason](const StrategyOptions&) -> std::unique_ptr<Strategy> {
        throw std::runtime_error(reason);
      });
}

const std::vector<StrategyEntry>& strategy_registry() {
  // One entry a line, in the order `list` and `run` show them: the papers' strategies, then the
  // baselines and peers a user would pick instead.
  // clang-format off
  static const std::vector<StrategyEntry> entries = {
      cpu_coxdeboor_entry(),
      gl_pingpong_entry(),
      gl_pingpong_packed_entry(),
      glsl_deboor_entry(),
      cl_stair_entry(),
      vk_ksquad_entry(),
      vk_compute_entry(),
      // T-splines (001): the CPU method, 001's split GPU passes, the Bézier-extraction paths.
      cpu_tspline_entry(),
      gl_tspline_entry(),
      cl_tspline_bezier_entry(),
      cpu_tspline_bezier_entry(),
      cpu_tensor_entry(),
      cpu_horner_entry(),
      cpu_bezier_entry(),
      vk_bezier_entry(),
      glu_nurbs_entry(),
      sisl_entry(),
      occt_entry(),
      occt_cached_entry(),
  };
  // clang-format on
  return entries;
}

namespace {
struct Added {
  StrategyEntry entry;
  StrategyLibrary library;
};
std::deque<Added>& added() {
  static std::deque<Added> entries;
  return entries;
}
}  // namespace

const StrategyEntry& add_strategy(StrategyEntry entry, StrategyLibrary library) {
  if (const StrategyEntry* taken = find_strategy(entry.name)) {
    const StrategyLibrary* from = strategy_library(*taken);
    throw std::invalid_argument(
        fmt::format("'{}' is already a strategy ({})", entry.name, from ? from->path : "built in"));
  }
  return added().emplace_back(Added{std::move(entry), std::move(library)}).entry;
}

const StrategyLibrary* strategy_library(const StrategyEntry& entry) {
  for (const Added& a : added())
    if (&a.entry == &entry) return &a.library;
  return nullptr;
}

std::vector<const StrategyEntry*> all_strategies() {
  std::vector<const StrategyEntry*> all;
  for (const StrategyEntry& e : strategy_registry()) all.push_back(&e);
  for (const Added& a : added()) all.push_back(&a.entry);
  return all;
}

const StrategyEntry* find_strategy(std::string_view name) {
  for (const StrategyEntry* e : all_strategies())
    if (e->name == name) return e;
  return nullptr;
}

std::vector<std::string> strategy_names() {
  std::vector<std::string> names;
  for (const StrategyEntry* e : all_strategies()) names.push_back(e->name);
  return names;
}

}  // namespace nurbs
