// The trim classification gates of results/gates.json as `nurbsbench check` applies them: they
// hold on a real run of the strategies that trim today, and a record above its gate (the same
// run's results with one strategy's misclassification raised, as a regressed classifier would
// write them) fails the check, exit 1, naming the strategy, scene and metric.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "run_cli.h"

namespace nurbs::test {
namespace {

using nlohmann::json;

TEST(CliTrimGates, HoldOnARealRunAndFailAStrategyAboveItsGate) {
  // The committed gates on classification, per strategy (not the "*" ones).
  json gates = json::array();
  std::set<std::string> scenes;
  for (const json& g :
       json::parse(read_text(std::string(NURBSBENCH_SOURCE_DIR) + "/results/gates.json")))
    if (g["metric"] == "trim_misclassified_rate" && g["strategy"] == "cpu-coxdeboor") {
      gates.push_back(g);
      scenes.insert(g["scene"].get<std::string>());
    }
  // One gate on every scene: a classification gate counts only trimmed scenes' records.
  ASSERT_EQ(scenes, (std::set<std::string>{"*"}));

  TempDir tmp;
  const std::string gates_file = tmp / "trim-gates.json";
  std::ofstream(gates_file) << gates.dump();
  const std::string results = tmp / "results";
  ASSERT_EQ(run_cli({"run", "--scenes", "trimmed-plate,hammer,many-ducks-2", "--strategies",
                     "cpu-coxdeboor", "--samples", "16x16", "--repetitions", "1", "--out", results})
                .exit_code,
            0);
  const CliResult holds = run_cli({"check", "--gates", gates_file, "--results", results});
  EXPECT_EQ(holds.exit_code, 0) << holds.out;

  json document = json::parse(read_text(results + "/results.json"));
  bool raised = false;
  for (json& r : document["records"])
    if (r["scene"] == "trimmed-plate") {
      json& trim = r["accuracy"]["trim"];
      ASSERT_EQ(trim["misclassified"], 0);  // what the real run measured
      trim["misclassified"] = 1;
      trim["misclassified_rate"] = 1.0 / (16 * 16);
      raised = true;
    }
  ASSERT_TRUE(raised);
  std::ofstream(results + "/results.json") << document.dump();
  const CliResult fails = run_cli({"check", "--gates", gates_file, "--results", results});
  EXPECT_EQ(fails.exit_code, 1) << fails.out;
  EXPECT_NE(fails.out.find("FAIL cpu-coxdeboor on trimmed-plate (f32, 16x16): "
                           "trim_misclassified_rate = 0.00390625 exceeds 0"),
            std::string::npos)
      << fails.out;
  EXPECT_EQ(fails.out.find("on hammer"), std::string::npos) << fails.out;
}

}  // namespace
}  // namespace nurbs::test
