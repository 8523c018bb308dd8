#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "harness/report/report.h"
#include "reference/validation.h"

namespace nurbs {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

template <typename File>
std::optional<File> read_if_present(const fs::path& path, File (*read)(const fs::path&)) {
  if (!fs::exists(path)) return std::nullopt;
  return read(path);
}

}  // namespace

ResultSet load_result_set(const fs::path& directory) {
  ResultSet set;
  set.directory = directory;
  const fs::path dir = fs::is_directory(directory) ? directory : directory.parent_path();
  // `nurbsbench lod`, `nurbsbench camera-path` and `nurbsbench memory --json` write their file
  // alone, so their regenerate commands (the verb, then report on the same directory) must read a
  // directory without results.json: a set with no records.
  const bool side_alone = fs::is_directory(directory) && !fs::exists(dir / "results.json") &&
                          (fs::exists(dir / "lod.json") || fs::exists(dir / "camera_path.json") ||
                           fs::exists(dir / "memory.json"));
  if (!side_alone) set.results = read_results(directory);
  fs::path name = fs::weakly_canonical(dir).filename();
  set.tag = name.empty() ? dir.string() : name.string();
  set.lod = read_if_present(dir / "lod.json", read_lod_file);
  set.memory = read_if_present(dir / "memory.json", read_memory_file);
  set.camera_path = read_if_present(dir / "camera_path.json", read_camera_path_file);
  // memory.json holds no machine: control-point memory does not depend on one.
  if (side_alone)
    set.results.machine = set.lod           ? set.lod->machine
                          : set.camera_path ? set.camera_path->machine
                                            : json::object();
  return set;
}

}  // namespace nurbs
