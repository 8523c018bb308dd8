// What the isolation tests share (tests/cli/isolation_test.cpp, and isolation_gpu_test.cpp with a
// GPU strategy): a run with a test fault injected through NURBSBENCH_INJECT_FAULT, and its
// records read back from results.json.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "run_cli.h"

namespace nurbs::test {

struct FaultRun {
  CliResult cli;
  // results.json's records; key "strategy scene".
  std::map<std::string, nlohmann::json> records;
  std::size_t record_count = 0;
  std::size_t csv_rows = 0;
};

// `nurbsbench run ARGS --out DIR` with NURBSBENCH_INJECT_FAULT=fault ("" for none); the variable
// is unset again afterwards (the tests run one at a time in their process).
inline FaultRun run_with_fault(const std::string& fault, std::vector<std::string> args,
                               const TempDir& tmp) {
  const std::string out = tmp / "results";
  args.insert(args.begin(), "run");
  args.insert(args.end(), {"--out", out});
  if (fault.empty())
    ::unsetenv("NURBSBENCH_INJECT_FAULT");
  else
    ::setenv("NURBSBENCH_INJECT_FAULT", fault.c_str(), 1);
  FaultRun run;
  run.cli = run_cli(args);
  ::unsetenv("NURBSBENCH_INJECT_FAULT");
  if (!std::filesystem::exists(std::filesystem::path(out) / "results.json")) return run;
  const nlohmann::json doc =
      nlohmann::json::parse(read_text(std::filesystem::path(out) / "results.json"));
  for (const nlohmann::json& r : doc["records"])
    run.records[r["strategy"].get<std::string>() + " " + r["scene"].get<std::string>()] = r;
  run.record_count = doc["records"].size();
  run.csv_rows = split_lines(read_text(std::filesystem::path(out) / "results.csv")).size() - 1;
  return run;
}

// Every record of `strategies` x `scenes` is there, once, in JSON and CSV; those of `faulty` have
// `status` with a reason containing each of `reason_parts`, every other one is ok.
inline void expect_only_faulty(const FaultRun& run, const std::vector<std::string>& strategies,
                               const std::vector<std::string>& scenes, const std::string& faulty,
                               const std::string& status,
                               const std::vector<std::string>& reason_parts) {
  ASSERT_EQ(run.cli.exit_code, 0) << run.cli.err;
  EXPECT_EQ(run.record_count, strategies.size() * scenes.size());
  EXPECT_EQ(run.csv_rows, strategies.size() * scenes.size());
  for (const std::string& strategy : strategies)
    for (const std::string& scene : scenes) {
      const auto it = run.records.find(strategy + " " + scene);
      ASSERT_NE(it, run.records.end()) << strategy << " on " << scene << " missing";
      const nlohmann::json& r = it->second;
      if (strategy != faulty) {
        EXPECT_EQ(r["status"], "ok") << r.dump();
        EXPECT_TRUE(r["accuracy"].is_object()) << r.dump();
        continue;
      }
      EXPECT_EQ(r["status"], status) << r.dump();
      for (const std::string& part : reason_parts)
        EXPECT_NE(r["reason"].get<std::string>().find(part), std::string::npos)
            << "'" << part << "' not in: " << r["reason"];
    }
}

}  // namespace nurbs::test
