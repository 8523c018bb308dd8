#include <iostream>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.h"
#include "harness/memory_table.h"
#include "reference/validation.h"
#include "scenes/builtin_scenes.h"

namespace nurbs::cli {

int memory_command(const MemoryOptions& options) {
  std::vector<MemoryRow> rows;
  for (const std::string& name : scene_list(options.scenes))
    rows.push_back(memory_row(load_scene(name)));
  if (rows.empty()) throw InputError("--scenes: empty list");
  if (options.json)
    std::cout << memory_table_json(rows).dump(2) << "\n";
  else
    std::cout << memory_table_text(rows);
  return 0;
}

}  // namespace nurbs::cli
