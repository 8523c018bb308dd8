// The nurbs-scene/1 and /2 JSON formats (docs/design.md §Scene file format; /2 adds a surface's
// "trim" and "orientation"): parse with every structural error named (file, surface, field path,
// index, value), unknown and duplicated keys refused, nesting and file size bounded; write in a
// form that reads back bit-identically (shortest round-trip numbers).
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

#include "reference/surface.h"

namespace nurbs {

inline constexpr std::string_view kSceneFormat = "nurbs-scene/1";
// Written only for a scene that needs it: a trimmed or reversed surface.
inline constexpr std::string_view kSceneFormat2 = "nurbs-scene/2";
// A scene file larger than this is refused before it is read: its JSON tree would take several
// times its size in memory.
inline constexpr std::uintmax_t kMaxSceneFileBytes = std::uintmax_t{1} << 30;

// The bytes of an input file of the named kind ("scene", "T-spline"), refused (InputError naming
// the file) when it cannot be read or is larger than kMaxSceneFileBytes.
std::string read_input_file(const std::filesystem::path& path, std::string_view kind);
// Any JSON file the user names (results, gates, side files), read as read_input_file() reads and
// parsed as scenes are (json_strict.h): one size limit, nesting bound, duplicate-key refusal and
// message style for every reader.
nlohmann::json read_json_strictly(const std::filesystem::path& path, std::string_view kind);

// Throws InputError (or its ValidationError) naming `origin`; the result is validated.
Scene parse_scene_json(std::string_view text, std::string_view origin);
Scene load_scene_file(const std::filesystem::path& path);
std::string scene_to_json(const Scene& scene);

}  // namespace nurbs
