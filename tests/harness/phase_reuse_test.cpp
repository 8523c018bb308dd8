// Honest phases (issue 30): the runner's repetitions read back into one result, and the CPU
// strategies copy into its buffers rather than allocating new ones, so upload and read_back after
// the first repetition pay no page faults. Asserted as page-fault counts and allocation identity,
// not as times: the spread of times follows from them on an idle machine, and CI's is not idle.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "harness/runner.h"
#include "scenes/builtin_scenes.h"
#include "strategies/registry.h"

namespace nurbs {
namespace {

// Fills every value with NaN, so a read back that skipped one is seen.
void poison(PointArray& a) {
  const std::size_t n = a.size() * 3;
  if (a.precision() == Precision::f32)
    for (std::size_t k = 0; k < n; ++k) a.f32()[k] = std::numeric_limits<float>::quiet_NaN();
  else
    for (std::size_t k = 0; k < n; ++k) a.f64()[k] = std::numeric_limits<double>::quiet_NaN();
}

const void* storage(const PointArray& a) {
  return a.precision() == Precision::f32 ? static_cast<const void*>(a.f32())
                                         : static_cast<const void*>(a.f64());
}

void expect_same_values(const PointArray& got, const PointArray& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  for (std::size_t k = 0; k < want.size(); ++k)
    ASSERT_EQ(got[k], want[k]) << what << " point " << k;
}

// Every host-CPU strategy that evaluates NURBS: a second prepare / evaluate / read_back_into
// writes the same values into the same allocations as the first.
TEST(HonestPhases, CpuStrategiesReadBackIntoTheBuffersTheyAreGiven) {
  const Scene scene = *make_builtin_scene("patch144");
  Sampling grid;
  grid.grid_u = 40;
  grid.grid_v = 24;
  int checked = 0;
  for (const char* name :
       {"cpu-tensor", "cpu-bezier", "cpu-horner", "cpu-coxdeboor", "sisl", "occt"}) {
    const StrategyEntry* entry = find_strategy(name);
    if (!entry || !entry->probe().available) continue;  // optional peers (sisl, occt)
    for (const Precision precision : {Precision::f32, Precision::f64}) {
      const EvalRequest request{grid, precision, /*normals=*/true};
      if (refusal_reason(entry->capabilities(), scene, request)) continue;
      const std::string what = fmt::format("{} {}", name, to_string(precision));
      std::unique_ptr<Strategy> strategy = entry->create({});
      strategy->prepare(scene, request);
      strategy->evaluate();
      EvalResult result;
      strategy->read_back_into(result);
      ASSERT_EQ(result.surfaces.size(), 1u) << what;
      const EvalResult first = result;
      const void* positions = storage(result.surfaces[0].positions);
      const void* normals = storage(result.surfaces[0].normals);
      poison(result.surfaces[0].positions);
      poison(result.surfaces[0].normals);
      strategy->prepare(scene, request);
      strategy->evaluate();
      strategy->read_back_into(result);
      EXPECT_EQ(storage(result.surfaces[0].positions), positions) << what;
      EXPECT_EQ(storage(result.surfaces[0].normals), normals) << what;
      expect_same_values(result.surfaces[0].positions, first.surfaces[0].positions, what);
      expect_same_values(result.surfaces[0].normals, first.surfaces[0].normals, what);
      // read_back() still gives a result of its own, equal to the one read into.
      const EvalResult fresh = strategy->read_back();
      expect_same_values(fresh.surfaces[0].positions, first.surfaces[0].positions, what);
      ++checked;
    }
  }
  EXPECT_GE(checked, 8);  // cpu-tensor, cpu-bezier, cpu-horner, cpu-coxdeboor at both precisions
}

// The GPU-API strategies likewise (strategies/host_results.h): on a scene of several surfaces, a
// second read_back_into writes the same values into the same allocations, surface by surface.
// Before, each read-back allocated an intermediate copy of the whole result and a fresh array per
// surface (read-back at 0.5-1 GB/s where the host strategies deliver 8-14).
TEST(HonestPhases, GpuApiStrategiesReadBackIntoTheBuffersTheyAreGiven) {
  const Scene scene = *make_builtin_scene("many-4");
  Sampling grid;
  grid.grid_u = 24;
  grid.grid_v = 16;
  for (const char* name : {"vk-compute", "vk-bezier", "vk-ksquad", "cl-stair", "glsl-deboor",
                           "gl-pingpong", "gl-pingpong-packed"}) {
    int checked = 0;
    const StrategyEntry* entry = find_strategy(name);
    ASSERT_NE(entry, nullptr) << name;
    if (!entry->probe().available) {
      // The release build with every backend (scripts/test.sh) has the software drivers.
      EXPECT_EQ(std::getenv("NURBSBENCH_REQUIRE_ALL_STRATEGIES"), nullptr)
          << name << ": " << entry->probe().reason;
      continue;
    }
    for (const Precision precision : {Precision::f32, Precision::f64})
      for (const bool normals : {false, true}) {
        const EvalRequest request{grid, precision, normals};
        if (refusal_reason(entry->capabilities(), scene, request)) continue;
        const std::string what =
            fmt::format("{} {}{}", name, to_string(precision), normals ? " normals" : "");
        std::unique_ptr<Strategy> strategy = entry->create({});
        strategy->prepare(scene, request);
        strategy->evaluate();
        EvalResult result;
        strategy->read_back_into(result);
        ASSERT_EQ(result.surfaces.size(), 4u) << what;
        const EvalResult first = result;
        std::vector<const void*> kept;
        for (SurfaceResult& r : result.surfaces) {
          ASSERT_EQ(r.positions.size(), 24u * 16) << what;
          kept.push_back(storage(r.positions));
          poison(r.positions);
          if (normals) {
            kept.push_back(storage(r.normals));
            poison(r.normals);
          }
        }
        strategy->prepare(scene, request);
        strategy->evaluate();
        strategy->read_back_into(result);
        ASSERT_EQ(result.surfaces.size(), 4u) << what;
        std::size_t k = 0;
        for (std::size_t i = 0; i < 4; ++i) {
          const std::string surface = fmt::format("{} surface {}", what, i);
          EXPECT_EQ(storage(result.surfaces[i].positions), kept[k++]) << surface;
          expect_same_values(result.surfaces[i].positions, first.surfaces[i].positions, surface);
          if (normals) {
            EXPECT_EQ(storage(result.surfaces[i].normals), kept[k++]) << surface;
            expect_same_values(result.surfaces[i].normals, first.surfaces[i].normals, surface);
          }
        }
        // read_back() still gives a result of its own, equal to the one read into.
        const EvalResult fresh = strategy->read_back();
        for (std::size_t i = 0; i < 4; ++i)
          expect_same_values(fresh.surfaces[i].positions, first.surfaces[i].positions, what);
        ++checked;
      }
    EXPECT_GE(checked, 1) << name << ": every request refused";
  }
}

// Through the runner, on an output larger than glibc's largest heap block (32 MiB: each array is
// then its own mapping, returned to the kernel when freed, so a fresh allocation per repetition
// faults on every page): the repetitions after the first take next to no faults in upload or
// read_back. Runs in about a second.
TEST(HonestPhases, RepetitionsAfterTheFirstTakeNoPageFaultsInUploadOrReadBack) {
  const Scene scene = *make_builtin_scene("patch144");
  Sampling grid;
  grid.grid_u = 2048;
  grid.grid_v = 1024;
  const EvalRequest request{grid, Precision::f64, /*normals=*/true};
  const StrategyEntry* entry = find_strategy("cpu-tensor");
  ASSERT_NE(entry, nullptr);
  Record r = measurement_record(*entry, scene, request, 3, 0);
  StrategyOptions options;
  options.threads = 2;
  ASSERT_TRUE(time_measurement(*entry, options, scene, request, 3, r)) << r.reason;
  // 2M points x (xyz + normal) x 8 bytes = 96 MiB: 24576 pages of 4 KiB.
  const double pages = 2048.0 * 1024 * 48 / 4096;
  ASSERT_TRUE(r.figures.contains("read_back_page_faults"));
  ASSERT_TRUE(r.figures.contains("upload_page_faults"));
  EXPECT_LT(r.figures.at("read_back_page_faults"), pages / 100);
  EXPECT_LT(r.figures.at("upload_page_faults"), pages / 100);
}

}  // namespace
}  // namespace nurbs
