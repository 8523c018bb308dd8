// The built-in T-spline scenes (001; the T-spline issue): a NURBS patch refined onto a T-mesh (the
// same surface, so its NURBS twin is an exact oracle), that T-mesh with its T-junction points
// moved (a surface no NURBS on that mesh has), and the Rhino T-Splines models that import
// (scenes/tsm/tsm_reader.h; scenes/data/tsplines/, LGPL).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "reference/surface.h"

namespace nurbs {

// `nurbs` (bicubic, clamped, at least 8x8 control points) refined by three face splits onto a
// T-mesh with six T-junctions (Sederberg et al. 2004): its T-spline evaluates to `nurbs`.
Scene tspline_refined_scene(const Surface& nurbs);
// The same T-mesh with the six T-junction control points lifted by `lift` along z.
Scene tspline_tjunction_scene(const Surface& nurbs, double lift);

// A `#TS0200` model's T-spline as a one-surface scene named `name`; `origin` prefixes errors, the
// description names `file`.
Scene tsm_scene(std::string_view bytes, const std::string& name, const std::string& origin,
                const std::string& file);
// A .tsm file given as a scene path (load_scene).
Scene tsm_file_scene(const std::filesystem::path& path);
bool is_tsm_path(const std::filesystem::path& path);

}  // namespace nurbs
