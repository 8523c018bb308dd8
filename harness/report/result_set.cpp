#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "harness/report/report.h"
#include "reference/validation.h"
#include "scenes/json_error.h"

namespace nurbs {

using nlohmann::json;
namespace fs = std::filesystem;

namespace {

std::optional<json> read_side_file(const fs::path& path, std::string_view format) {
  if (!fs::exists(path)) return std::nullopt;
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("{}: cannot open", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  json document;
  try {
    document = json::parse(text.str());
  } catch (const json::exception& e) {
    throw InputError(fmt::format("{}: not JSON: {}", path.string(), json_error_text(e)));
  }
  if (!document.is_object() || !document.contains("format") || document["format"] != format)
    throw InputError(fmt::format("{}: format = {}: must be \"{}\"", path.string(),
                                 document.is_object() && document.contains("format")
                                     ? document["format"].dump()
                                     : "(missing)",
                                 format));
  if (!document.contains("rows") || !document["rows"].is_array())
    throw InputError(
        fmt::format("{}: rows = {}: must be a list", path.string(),
                    document.contains("rows") ? document["rows"].dump() : "(missing)"));
  for (std::size_t i = 0; i < document["rows"].size(); ++i)
    if (!document["rows"][i].is_object())
      throw InputError(fmt::format("{}: rows[{}] = {}: must be an object", path.string(), i,
                                   document["rows"][i].dump()));
  return document;
}

}  // namespace

ResultSet load_result_set(const fs::path& directory) {
  ResultSet set;
  set.directory = directory;
  const fs::path dir = fs::is_directory(directory) ? directory : directory.parent_path();
  // `nurbsbench lod` and `nurbsbench camera-path` write their file alone, so their regenerate
  // commands (the verb, then report on the same directory) must read a directory without
  // results.json: a set with no records.
  const bool side_alone = fs::is_directory(directory) && !fs::exists(dir / "results.json") &&
                          (fs::exists(dir / "lod.json") || fs::exists(dir / "camera_path.json"));
  if (!side_alone) set.results = read_results(directory);
  fs::path name = fs::weakly_canonical(dir).filename();
  set.tag = name.empty() ? dir.string() : name.string();
  set.lod = read_side_file(dir / "lod.json", "nurbsbench-lod/1");
  set.memory = read_side_file(dir / "memory.json", "nurbsbench-memory/1");
  set.camera_path = read_side_file(dir / "camera_path.json", "nurbsbench-camera-path/1");
  if (side_alone)
    set.results.machine = (set.lod ? *set.lod : *set.camera_path).value("machine", json::object());
  return set;
}

}  // namespace nurbs
