#include <iostream>

#include "harness/atomic_file.h"
#include "harness/cli/commands.h"
#include "scenes/builtin_scenes.h"
#include "scenes/scene_json.h"

namespace nurbs::cli {

int scene_command(const SceneOptions& options) {
  const std::string json = scene_to_json(load_scene(options.scene));
  if (options.out.empty() || options.out == "-")
    std::cout << json;
  else
    write_file_atomically(options.out, json);
  return 0;
}

}  // namespace nurbs::cli
