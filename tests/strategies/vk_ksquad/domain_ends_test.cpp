// vk-ksquad at domain ends that are not floats (issue 28), in every mode: grid and span grid
// (uniform), the GS mapping, adaptive and nonuniform -- every sample finite and on the surface
// (domain_ends.h). The host assigns every sample its KSQuad (ksquad::runs_of_grid clamps by A2.1's
// search; span grids and the tessellator's samples are per KSQuad by construction), so a float
// parameter rounded outward at a domain end is evaluated in the end span, as the reference does,
// within half a float ulp of the end.
#include "tests/strategies/domain_ends.h"

#include <gtest/gtest.h>

#include <iostream>
#include <map>
#include <string>

#include "strategies/registry.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"
#include "tests/reference/test_support.h"

namespace nurbs {
namespace {

TEST(vk_ksquad_domain_ends, EveryModeStaysOnTheSurface) {
  const Availability a = find_strategy("vk-ksquad")->probe();
  if (!a.available) GTEST_SKIP() << "unavailable: " << a.reason;
  const Scene scene = test::unrepresentable_ends_scene();
  struct Run {
    const char* mode;
    Sampling sampling;
  };
  const Run runs[] = {{"uniform", test::grid(17, 13)},
                      {"uniform", test::span_grid(5)},
                      {"gs", test::span_grid(4)},
                      {"adaptive", test::span_grid(1)},
                      {"nonuniform", test::span_grid(1)}};
  for (const Run& run : runs) {
    const std::string label = std::string(run.mode) + " " + run.sampling.label();
    StrategyOptions options;
    options.extra = {{"vk-mode", run.mode}};
    auto strategy = make_vk_ksquad(options);
    strategy->prepare(scene, EvalRequest{run.sampling, Precision::f32, false});
    strategy->evaluate();
    const EvalResult result = strategy->read_back();
    const std::size_t checked = test::expect_on_surface(scene, result, 64, label);
    EXPECT_GT(checked, 0u) << label;
    std::cout << label << ": " << checked << " samples finite and on the surface\n";
  }
}

}  // namespace
}  // namespace nurbs
