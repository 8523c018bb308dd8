// The canonical scenes of the papers and the stress cases, generated in code (deterministic) or
// embedded at build time (teapot, duck: real third-party data converted once into scenes/data/).
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "reference/surface.h"

namespace nurbs {

struct BuiltinSceneInfo {
  std::string name;
  std::string description;
};

// The listed names; `many-N` accepts any N in 1..kMaxManyPatches, three are listed.
std::vector<BuiltinSceneInfo> builtin_scenes();
inline constexpr int kMaxManyPatches = 4096;

// nullopt when `name` is not a built-in scene. The scene is validated.
std::optional<Scene> make_builtin_scene(std::string_view name);

// A workload described by its parameters (`nurbsbench recommend --degree --control-net
// --surfaces`): `surfaces` copies of the degree-N scenes' smooth control net, tiled side by side,
// uniform clamped knots. Throws InputError for parameters a scene cannot have.
Scene workload_scene(int degree, int count_u, int count_v, int surfaces);

// A built-in name or a path to a nurbs-scene/1 or /2 file. Throws InputError naming the valid names
// when it is neither.
Scene load_scene(std::string_view name_or_path);

}  // namespace nurbs
