#include <fmt/format.h>

#include <iostream>

#include "harness/cli/commands.h"
#include "harness/gates.h"
#include "harness/results_writer.h"

namespace nurbs::cli {

int check_command(const CheckOptions& options) {
  const std::vector<Gate> gates = load_gates(options.gates);
  const ResultsFile results = read_results(options.results);
  const std::vector<std::string> violations = check_gates(gates, results.records);
  for (const std::string& v : violations) std::cout << "FAIL " << v << "\n";
  std::cout << fmt::format("{} gates checked against {} results: {} violation{}\n", gates.size(),
                           results.records.size(), violations.size(),
                           violations.size() == 1 ? "" : "s");
  return violations.empty() ? 0 : 1;
}

}  // namespace nurbs::cli
