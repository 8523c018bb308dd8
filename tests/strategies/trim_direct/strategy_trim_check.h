// A trimming strategy's classify() on a built-in scene against the reference classifier, for the
// device tests of cl-stair and vk-ksquad: 0 misclassified outside the band, the cost counter in
// DeviceInfo::details within the bound of the tables (trim_direct_check.h).
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"
#include "tests/strategies/trim_direct/trim_direct_check.h"

namespace nurbs::test {

inline void expect_strategy_trims_exactly(const std::string& strategy, const Scene& scene,
                                          const std::string& scene_name, const Sampling& sampling,
                                          Precision precision,
                                          const StrategyOptions& options = {}) {
  SCOPED_TRACE(strategy + " on " + scene_name);
  auto s = find_strategy(strategy)->create(options);
  ASSERT_TRUE(s->capabilities().trims);
  s->prepare(scene, EvalRequest{sampling, precision, false});
  s->evaluate();
  ASSERT_TRUE(s->classify());
  const EvalResult result = s->read_back();
  TrimMismatch total;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const SurfaceResult& r = result.surfaces[i];
    if (!scene.surfaces[i].trim) {
      EXPECT_TRUE(r.inside.empty());
      continue;
    }
    ASSERT_EQ(r.inside.size(), r.samples.count()) << "surface " << i;
    total += compare_with_reference(scene.surfaces[i], r.samples, r.inside);
  }
  EXPECT_EQ(total.misclassified, 0u);
  EXPECT_GT(total.inside, 0u);
  EXPECT_LT(total.inside, total.compared);
  // The cost counter, as the device counted it: positive, and at most the tables' bound (built
  // here in the device's scalar; float for the Vulkan stages and f32 OpenCL).
  const auto details = s->device().details;
  ASSERT_TRUE(details.count("trim_reads_per_sample_max"));
  const int max_reads = std::stoi(details.at("trim_reads_per_sample_max"));
  const double mean_reads = std::stod(details.at("trim_reads_per_sample_mean"));
  const int bound =
      precision == Precision::f32
          ? max_reads_bound(trim_direct::build_tables<float>(scene, trim_direct::Settings{}))
          : max_reads_bound(trim_direct::build_tables<double>(scene, trim_direct::Settings{}));
  EXPECT_GE(mean_reads, 1.0);
  EXPECT_LE(mean_reads, max_reads);
  EXPECT_LE(max_reads, bound);
  std::printf(
      "%s %s: %zu of %zu outside the band misclassified (%zu in it); reads per sample "
      "mean %.2f max %d (bound %d)\n",
      strategy.c_str(), scene_name.c_str(), total.misclassified, total.compared, total.in_band,
      mean_reads, max_reads, bound);
}

inline void expect_strategy_trims_exactly(const std::string& strategy,
                                          const std::string& scene_name, const Sampling& sampling,
                                          Precision precision,
                                          const StrategyOptions& options = {}) {
  expect_strategy_trims_exactly(strategy, *make_builtin_scene(scene_name), scene_name, sampling,
                                precision, options);
}

// Every invalid trim-epsilon / trim-iterations is refused by `create` (a strategy's factory, or
// trim_direct::settings_from) with an error naming `strategy`, the option and the value.
inline void expect_trim_options_refused(const std::function<void(const StrategyOptions&)>& create,
                                        const std::string& strategy) {
  for (const auto& [key, value] :
       std::vector<std::pair<std::string, std::string>>{{"trim-epsilon", "0"},
                                                        {"trim-epsilon", "-1e-3"},
                                                        {"trim-epsilon", "2"},
                                                        {"trim-epsilon", "1e-6x"},
                                                        {"trim-epsilon", "nan"},
                                                        {"trim-iterations", "0"},
                                                        {"trim-iterations", "65"},
                                                        {"trim-iterations", "ten"}}) {
    StrategyOptions o;
    o.extra[key] = value;
    try {
      create(o);
      ADD_FAILURE() << key << "=" << value << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(strategy + " option " + key + " = '" + value + "'"),
                std::string::npos)
          << e.what();
    }
  }
}

inline Sampling trim_grid(int n) {
  Sampling s;
  s.grid_u = n;
  s.grid_v = n + 3;  // not square: rows and columns differ
  return s;
}

inline Sampling trim_span_grid(int steps) {
  Sampling s;
  s.mode = SamplingMode::span_grid;
  s.span_steps = steps;
  return s;
}

// The device tests of a trimming strategy: trimmed-plate (grid, span grid, and f64 where the
// strategy has it) and the hammer (grid, span grid), then its options.
inline void expect_trimmed_plate_exact(const std::string& strategy) {
  expect_strategy_trims_exactly(strategy, "trimmed-plate", trim_grid(97), Precision::f32);
  expect_strategy_trims_exactly(strategy, "trimmed-plate", trim_span_grid(16), Precision::f32);
  if (find_strategy(strategy)->capabilities().fp64)
    expect_strategy_trims_exactly(strategy, "trimmed-plate", trim_grid(64), Precision::f64);
}

inline void expect_hammer_exact(const std::string& strategy) {
  expect_strategy_trims_exactly(strategy, "hammer", trim_grid(33), Precision::f32);
  expect_strategy_trims_exactly(strategy, "hammer", trim_span_grid(3), Precision::f32);
}

inline void expect_strategy_refuses_trim_options(const std::string& strategy) {
  expect_trim_options_refused([&](const StrategyOptions& o) { find_strategy(strategy)->create(o); },
                              strategy);
}

}  // namespace nurbs::test
