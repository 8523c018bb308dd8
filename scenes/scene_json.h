// The nurbs-scene/1 JSON format (DESIGN.md, "Scene file format"): parse with every structural
// error named (file, surface, field, index, value), unknown keys refused; write in a form that
// reads back bit-identically (shortest round-trip numbers).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "reference/surface.h"

namespace nurbs {

inline constexpr std::string_view kSceneFormat = "nurbs-scene/1";

// Throws InputError (or its ValidationError) naming `origin`; the result is validated.
Scene parse_scene_json(std::string_view text, std::string_view origin);
Scene load_scene_file(const std::filesystem::path& path);
std::string scene_to_json(const Scene& scene);

}  // namespace nurbs
