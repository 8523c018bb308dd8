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

constexpr const char* kSideFiles[] = {"lod.json", "camera_path.json", "memory.json"};

bool has_side_file(const fs::path& dir) {
  return std::any_of(std::begin(kSideFiles), std::end(kSideFiles),
                     [&](const char* name) { return fs::exists(dir / name); });
}

bool is_set_directory(const fs::path& dir) {
  return fs::exists(dir / "results.json") || has_side_file(dir);
}

}  // namespace

ResultSet load_result_set(const fs::path& directory) {
  ResultSet set;
  set.directory = directory;
  const fs::path dir = fs::is_directory(directory) ? directory : directory.parent_path();
  // `nurbsbench lod`, `nurbsbench camera-path` and `nurbsbench memory --json` write their file
  // alone, so their regenerate commands (the verb, then report on the same directory) must read a
  // directory without results.json: a set with no records.
  const bool side_alone =
      fs::is_directory(directory) && !fs::exists(dir / "results.json") && has_side_file(dir);
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

std::vector<ResultSet> load_result_sets(const fs::path& path) {
  if (!fs::is_directory(path) || is_set_directory(path)) return {load_result_set(path)};
  std::vector<fs::path> found;
  std::error_code error;
  for (auto it = fs::recursive_directory_iterator(path, error);
       !error && it != fs::recursive_directory_iterator(); it.increment(error)) {
    if (!it->is_directory()) continue;
    // A report folder holds charts.json and images, never a set.
    if (it->path().filename() == "report") {
      it.disable_recursion_pending();
      continue;
    }
    if (is_set_directory(it->path())) found.push_back(it->path());
  }
  if (error)
    throw InputError(fmt::format("{}: cannot list the results sets below it: {}", path.string(),
                                 error.message()));
  if (found.empty()) return {load_result_set(path)};
  std::sort(found.begin(), found.end());
  std::vector<ResultSet> sets;
  for (const fs::path& dir : found) sets.push_back(load_result_set(dir));
  return sets;
}

}  // namespace nurbs
