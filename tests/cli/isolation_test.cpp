// Runs that survive their strategies (issue 14): each measurement in its own process, a watchdog,
// the CTS-ordered statuses, driven through the project's own fault injection
// (NURBSBENCH_INJECT_FAULT) on CPU strategies. The GPU variant is isolation_gpu_test.cpp.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "isolation_faults.h"
#include "run_cli.h"

namespace nurbs::test {
namespace {

using nlohmann::json;

const std::vector<std::string> kStrategies = {"cpu-coxdeboor", "cpu-bezier", "cpu-tensor"};
const std::vector<std::string> kScenes = {"patch144", "tan16"};

std::vector<std::string> issue_run(std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {
      "--scenes",  "patch144,tan16", "--strategies",  "cpu-coxdeboor,cpu-bezier,cpu-tensor",
      "--samples", "16x16",          "--repetitions", "1"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// The issue's run, with the middle strategy crashing in evaluate: before isolation the whole run
// died after its first record.
TEST(Isolation, CrashCostsOnlyItsOwnRecords) {
  TempDir tmp;
  const FaultRun run = run_with_fault("cpu-bezier:evaluate:crash", issue_run(), tmp);
  expect_only_faulty(run, kStrategies, kScenes, "cpu-bezier", "crashed",
                     {"SIGSEGV (Segmentation fault)", "in evaluate"});
  EXPECT_NE(run.cli.out.find("statuses: 4 ok, 2 crashed\n"), std::string::npos) << run.cli.out;
}

TEST(Isolation, HangIsKilledByTheWatchdogAndNamesThePhase) {
  TempDir tmp;
  const FaultRun run =
      run_with_fault("cpu-bezier:read_back:hang",
                     {"--scenes", "patch144", "--strategies", "cpu-coxdeboor,cpu-bezier,cpu-tensor",
                      "--samples", "16x16", "--repetitions", "1", "--timeout", "2"},
                     tmp);
  expect_only_faulty(run, kStrategies, {"patch144"}, "cpu-bezier", "timed_out",
                     {"within 2 s", "in read_back"});
  EXPECT_NE(run.cli.out.find("statuses: 2 ok, 1 timed_out\n"), std::string::npos) << run.cli.out;
  const json settings = json::parse(read_text(tmp.path() / "results" / "results.json"))["settings"];
  EXPECT_EQ(settings["timeout_s"], 2.0);
  EXPECT_EQ(settings["isolation"], "process");
}

TEST(Isolation, ThrowIsFailedWithItsMessage) {
  TempDir tmp;
  const FaultRun run = run_with_fault("cpu-bezier:prepare:throw", issue_run(), tmp);
  expect_only_faulty(run, kStrategies, kScenes, "cpu-bezier", "failed",
                     {"injected fault: throw in prepare"});
}

// A crash while the factory builds the strategy is named "setup".
TEST(Isolation, CrashInSetupNamesSetup) {
  TempDir tmp;
  const FaultRun run = run_with_fault("cpu-tensor:setup:crash", issue_run(), tmp);
  expect_only_faulty(run, kStrategies, kScenes, "cpu-tensor", "crashed", {"in setup"});
}

// NaN positions are a wrong answer, never a measurement (issue 28): failed, with the count and the
// first sample, the accuracy still recorded (the error infinite, null in JSON), and every gate on
// the strategy violated.
TEST(Isolation, NanIsFailedWithCountAndFirstSampleAndFailsItsGate) {
  TempDir tmp;
  const FaultRun run = run_with_fault("cpu-bezier:read_back:nan", issue_run(), tmp);
  expect_only_faulty(run, kStrategies, kScenes, "cpu-bezier", "failed",
                     {"256 of 256 samples are not finite", "the first at surface 0 (u, v) = ("});
  for (const std::string& scene : kScenes) {
    const json& r = run.records.at("cpu-bezier " + scene);
    EXPECT_EQ(r["accuracy"]["non_finite"], 256) << r.dump();
    EXPECT_TRUE(r["accuracy"]["max_abs"].is_null()) << r.dump();
  }
  const std::string gates = tmp / "gates.json";
  write_text(gates, R"([{"strategy": "cpu-bezier", "scene": "*", "metric": "max_abs", "max": 1}])");
  const CliResult check =
      run_cli({"check", "--gates", gates, "--results", (tmp.path() / "results").string()});
  EXPECT_EQ(check.exit_code, 1) << check.out << check.err;
  EXPECT_NE(check.out.find("max_abs <= 1 not measured: failed: 256 of 256 samples are not finite"),
            std::string::npos)
      << check.out;
}

// eval writes the points it got (they are what to look at) and exits 1 naming the first NaN.
TEST(Isolation, EvalWithNanExitsOneAndNamesTheFirstSample) {
  TempDir tmp;
  const std::string out = tmp / "points.csv";
  ::setenv("NURBSBENCH_INJECT_FAULT", "cpu-bezier:read_back:nan", 1);
  const CliResult r = run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-bezier",
                               "--samples", "4x4", "--out", out});
  ::unsetenv("NURBSBENCH_INJECT_FAULT");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("nurbsbench: cpu-bezier on patch144: 16 of 16 samples are not finite"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("the first at surface 0 (u, v) = (0, 0)"), std::string::npos) << r.err;
  EXPECT_EQ(split_lines(read_text(out)).size(), 17u) << "header and 16 points";
  const CliResult clean = run_cli({"eval", "--scene", "patch144", "--strategy", "cpu-bezier",
                                   "--samples", "4x4", "--out", out});
  EXPECT_EQ(clean.exit_code, 0) << clean.err;
}

TEST(Isolation, CheckTreatsCrashedAndTimedOutAsViolations) {
  TempDir tmp;
  const FaultRun run =
      run_with_fault("cpu-bezier:evaluate:crash",
                     {"--scenes", "patch144", "--strategies", "cpu-coxdeboor,cpu-bezier",
                      "--samples", "8x8", "--repetitions", "1"},
                     tmp);
  ASSERT_EQ(run.cli.exit_code, 0) << run.cli.err;
  const std::string gates = tmp / "gates.json";
  const std::string results = (tmp.path() / "results").string();
  write_text(gates,
             R"([{"strategy": "cpu-coxdeboor", "scene": "*", "metric": "max_ulp", "max": 64}])");
  EXPECT_EQ(run_cli({"check", "--gates", gates, "--results", results}).exit_code, 0);
  write_text(gates, R"([{"strategy": "cpu-*", "scene": "*", "metric": "max_ulp", "max": 64}])");
  const CliResult check = run_cli({"check", "--gates", gates, "--results", results});
  EXPECT_EQ(check.exit_code, 1) << check.out << check.err;
  EXPECT_NE(check.out.find("FAIL cpu-bezier on patch144 (f32, 8x8): max_ulp <= 64 not measured: "
                           "crashed: SIGSEGV (Segmentation fault) in evaluate"),
            std::string::npos)
      << check.out;
  EXPECT_NE(check.out.find("1 violation\n"), std::string::npos) << check.out;
}

// The deforming benchmark goes through the same isolation; its update phase is named.
TEST(Isolation, DeformingRunIsIsolatedToo) {
  TempDir tmp;
  const FaultRun run = run_with_fault("cpu-bezier:update:crash",
                                      {"--deforming", "2", "--scenes", "patch144", "--strategies",
                                       "cpu-bezier,cpu-coxdeboor", "--samples", "8x8"},
                                      tmp);
  expect_only_faulty(run, {"cpu-bezier", "cpu-coxdeboor"}, {"patch144"}, "cpu-bezier", "crashed",
                     {"in update"});
  EXPECT_EQ(run.records.at("cpu-coxdeboor patch144")["figures"]["frames"], 2);
}

// --isolation none is today's in-process mode: the same records, statuses and accuracy.
TEST(Isolation, InProcessModeGivesTheSameMeasurement) {
  TempDir a, b;
  // trimmed-plate: cpu-coxdeboor's inside masks cross the process boundary and are scored there.
  const std::vector<std::string> args = {"--scenes",      "patch144,trimmed-plate",
                                         "--strategies",  "cpu-coxdeboor,cpu-bezier",
                                         "--samples",     "8x8",
                                         "--repetitions", "1"};
  std::vector<std::string> none = args;
  none.insert(none.end(), {"--isolation", "none"});
  const FaultRun isolated = run_with_fault("", args, a);
  const FaultRun in_process = run_with_fault("", none, b);
  ASSERT_EQ(isolated.cli.exit_code, 0) << isolated.cli.err;
  ASSERT_EQ(in_process.cli.exit_code, 0) << in_process.cli.err;
  ASSERT_EQ(in_process.record_count, 4u);
  EXPECT_EQ(isolated.records.at("cpu-coxdeboor trimmed-plate")["trimming"], "classified");
  for (const auto& [key, r] : in_process.records) {
    EXPECT_EQ(r["status"], "ok") << r.dump();
    // Same strategy, same samples, same arithmetic: the same error, bit for bit.
    EXPECT_EQ(r["accuracy"], isolated.records.at(key)["accuracy"]) << key;
    EXPECT_EQ(r["points"], 64);
  }
  EXPECT_EQ(json::parse(read_text(b.path() / "results" / "results.json"))["settings"]["isolation"],
            "none");
}

// recommend's quick run measures through the same isolation: a crashed strategy is excluded with
// its status, the others are ranked.
TEST(Isolation, RecommendQuickRunSurvivesACrash) {
  ::setenv("NURBSBENCH_INJECT_FAULT", "cpu-bezier:evaluate:crash", 1);
  const CliResult r = run_cli({"recommend", "--scene", "patch144", "--samples", "8x8",
                               "--tolerance", "8ulp", "--repetitions", "1", "--json"});
  ::unsetenv("NURBSBENCH_INJECT_FAULT");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json doc = json::parse(r.out);  // stdout is the JSON alone: children write to stderr
  bool excluded = false;
  for (const json& e : doc["excluded"])
    if (e.dump().find("cpu-bezier") != std::string::npos) {
      excluded = true;
      EXPECT_NE(e.dump().find("crashed"), std::string::npos) << e.dump();
    }
  EXPECT_TRUE(excluded) << doc["excluded"].dump();
  bool coxdeboor_ranked = false;
  for (const json& e : doc["ranked"])
    coxdeboor_ranked = coxdeboor_ranked || e.dump().find("cpu-coxdeboor") != std::string::npos;
  EXPECT_TRUE(coxdeboor_ranked) << doc["ranked"].dump();
}

TEST(Isolation, BadOptionsAndFaultSpecsAreUsageErrors) {
  TempDir tmp;
  for (const auto& [fault, args, message] :
       std::vector<std::tuple<std::string, std::vector<std::string>, std::string>>{
           {"cpu-bezier:evaluate", {}, "NURBSBENCH_INJECT_FAULT=cpu-bezier:evaluate: three fields"},
           {"no-such:evaluate:crash", {}, "'no-such' is not a strategy"},
           {"cpu-bezier:draw:crash", {}, "unknown phase 'draw'"},
           {"cpu-bezier:evaluate:nan", {}, "nan corrupts what read_back returns"},
           {"", {"--timeout", "0"}, "--timeout = 0"},
           {"", {"--device-timeout", "-1"}, "--device-timeout = -1"},
           {"", {"--isolation", "thread"}, "--isolation"}}) {
    std::vector<std::string> full = {"--scenes", "patch144", "--strategies", "cpu-coxdeboor"};
    full.insert(full.end(), args.begin(), args.end());
    const FaultRun run = run_with_fault(fault, full, tmp);
    EXPECT_EQ(run.cli.exit_code, 2) << fault << " " << run.cli.err;
    EXPECT_TRUE(is_one_error_line(run.cli.err)) << run.cli.err;
    EXPECT_NE(run.cli.err.find(message), std::string::npos) << run.cli.err;
    EXPECT_FALSE(std::filesystem::exists(tmp.path() / "results")) << "no output on bad input";
  }
}

}  // namespace
}  // namespace nurbs::test
