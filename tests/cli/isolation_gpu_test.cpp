// Isolation with GPU strategies (issue 14's "done means"): the run with a fault in
// cl-stair's OpenCL kernel launch finishes with every other measurement ok, GL strategies run
// in the forked children, and a Vulkan strategy that hangs is timed_out by the watchdog.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "isolation_faults.h"
#include "run_cli.h"

namespace nurbs::test {
namespace {

// The command: before isolation it died of SIGSEGV after its first record.
TEST(IsolationGpu, CrashInTheOpenClLaunchCostsOnlyItsRecords) {
  TempDir tmp;
  const FaultRun run = run_with_fault(
      "cl-stair:evaluate:crash",
      {"--scenes", "patch144,tan16", "--strategies", "cpu-coxdeboor,cl-stair,cpu-tensor",
       "--samples", "16x16", "--repetitions", "1"},
      tmp);
  expect_only_faulty(run, {"cpu-coxdeboor", "cl-stair", "cpu-tensor"}, {"patch144", "tan16"},
                     "cl-stair", "crashed", {"SIGSEGV (Segmentation fault)", "in evaluate"});
}

// GL and OpenCL strategies work in the children the measurement server forks (it never touched
// a driver); the faulty one is GL here.
TEST(IsolationGpu, GpuStrategiesRunInChildrenAndAGlCrashIsContained) {
  TempDir tmp;
  const FaultRun run =
      run_with_fault("gl-pingpong:read_back:crash",
                     {"--scenes", "patch144", "--strategies", "glsl-deboor,gl-pingpong,cl-stair",
                      "--samples", "16x16", "--repetitions", "1"},
                     tmp);
  expect_only_faulty(run, {"glsl-deboor", "gl-pingpong", "cl-stair"}, {"patch144"}, "gl-pingpong",
                     "crashed", {"in read_back"});
}

TEST(IsolationGpu, VulkanHangIsTimedOut) {
  TempDir tmp;
  const FaultRun run =
      run_with_fault("vk-ksquad:evaluate:hang",
                     {"--scenes", "patch144", "--strategies", "vk-ksquad,cpu-coxdeboor",
                      "--samples", "16x16", "--repetitions", "1", "--timeout", "15"},
                     tmp);
  // 15 s, not less: lavapipe's pipeline builds in prepare took over 5 s on a loaded 2-core
  // machine, and the hang must be the one that times out.
  expect_only_faulty(run, {"vk-ksquad", "cpu-coxdeboor"}, {"patch144"}, "vk-ksquad", "timed_out",
                     {"within 15 s", "in evaluate"});
}

}  // namespace
}  // namespace nurbs::test
