#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "harness/gbench_json.h"

namespace nurbs::cli {

int gbench_command(const GbenchOptions& options) {
  const std::string text = gbench_json(read_results(options.results)).dump(2) + "\n";
  if (options.out.empty() || options.out == "-")
    std::cout << text;
  else
    write_file_atomically(options.out, text);
  return 0;
}

}  // namespace nurbs::cli
