#include "harness/side_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <limits>

#include "reference/validation.h"
#include "scenes/scene_json.h"

namespace nurbs {

using nlohmann::json;

namespace {

// One object of a side file being read: its file and its place ("rows[2].levels[0]") for errors.
class Fields {
 public:
  Fields(const std::filesystem::path& file, const json& object, std::string where)
      : file_(file), object_(object), where_(std::move(where)) {}

  const json& object() const { return object_; }
  std::string field(const char* key) const {
    return where_.empty() ? std::string(key) : where_ + "." + key;
  }
  [[noreturn]] void fail(const char* key, const json& value, std::string_view must) const {
    throw InputError(fmt::format("{}: {} = {}: {}", file_.string(), field(key),
                                 value.is_discarded() ? "(missing)" : value.dump(), must));
  }
  const json& at(const char* key) const {
    static const json missing(json::value_t::discarded);
    const auto it = object_.find(key);
    if (it == object_.end()) fail(key, missing, "required");
    return *it;
  }
  bool has(const char* key) const {
    const auto it = object_.find(key);
    return it != object_.end() && !it->is_null();
  }
  Fields child(const char* key) const {
    const json& value = at(key);
    if (!value.is_object()) fail(key, value, "must be an object");
    return {file_, value, field(key)};
  }
  // Each element of the list under `key`, as objects.
  std::vector<Fields> list(const char* key) const {
    const json& value = at(key);
    if (!value.is_array()) fail(key, value, "must be a list");
    std::vector<Fields> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
      const std::string name = fmt::format("{}[{}]", field(key), i);
      if (!value[i].is_object())
        throw InputError(
            fmt::format("{}: {} = {}: must be an object", file_.string(), name, value[i].dump()));
      out.emplace_back(file_, value[i], name);
    }
    return out;
  }
  std::string text(const char* key) const {
    const json& v = at(key);
    if (!v.is_string()) fail(key, v, "must be a string");
    return v.get<std::string>();
  }
  double number(const char* key) const {
    const json& v = at(key);
    if (!v.is_number()) fail(key, v, "must be a number");
    return v.get<double>();
  }
  template <typename Int>
  Int integer(const char* key) const {
    const json& v = at(key);
    // nlohmann reads a non-negative integer as unsigned: a signed field takes either.
    if (std::numeric_limits<Int>::is_signed ? !v.is_number_integer() : !v.is_number_unsigned())
      fail(key, v,
           std::numeric_limits<Int>::is_signed ? "must be an integer"
                                               : "must be a non-negative integer");
    return v.get<Int>();
  }
  std::optional<double> optional_number(const char* key) const {
    return has(key) ? std::optional(number(key)) : std::nullopt;
  }
  template <typename Int>
  std::optional<Int> optional_integer(const char* key) const {
    return has(key) ? std::optional(integer<Int>(key)) : std::nullopt;
  }
  std::array<double, 3> point(const char* key) const {
    const json& v = at(key);
    if (!v.is_array() || v.size() != 3 ||
        !std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); }))
      fail(key, v, "must be a list of 3 numbers");
    return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
  }

 private:
  const std::filesystem::path& file_;
  const json& object_;
  std::string where_;
};

// The document of a side file: JSON, an object of the given format (its rows are read by Fields).
json read_document(const std::filesystem::path& path, std::string_view format) {
  const json document = read_json_strictly(path, "side");
  if (!document.is_object() || !document.contains("format") || document["format"] != format)
    throw InputError(fmt::format("{}: format = {}: must be \"{}\"", path.string(),
                                 document.is_object() && document.contains("format")
                                     ? document["format"].dump()
                                     : "(missing)",
                                 format));
  return document;
}

json object_or_empty(const json& document, const char* key) {
  return document.contains(key) && document[key].is_object() ? document[key] : json::object();
}

SideDevice device_of(const Fields& row) {
  const Fields d = row.child("device");
  return {d.text("name"), d.text("kind")};
}

std::optional<LodDrawFields> draw_of(const Fields& f) {
  if (!f.has("render_s")) return std::nullopt;
  return LodDrawFields{f.number("render_s"), f.integer<std::int64_t>("index_elements"),
                       f.integer<std::int64_t>("drawn_pixels")};
}

CameraCounts counts_of(const Fields& f) {
  return {f.integer<std::uint64_t>("draws"), f.integer<std::uint64_t>("passes"),
          f.integer<std::uint64_t>("host_read_backs"), f.integer<std::uint64_t>("device_copies")};
}

template <typename T>
void put_optional(json& j, const char* key, const std::optional<T>& value) {
  if (value) j[key] = *value;
}

}  // namespace

void to_json(json& j, const SideDevice& d) {
  j = {{"name", d.name}, {"kind", d.kind}};
}
void to_json(json& j, const LodDrawFields& d) {
  j = {{"render_s", d.render_s},
       {"index_elements", d.index_elements},
       {"drawn_pixels", d.drawn_pixels}};
}
void to_json(json& j, const LodLevelRow& r) {
  j = {{"level", r.level},
       {"samples", r.samples},
       {"max_distance", r.max_distance},
       {"max_ulp", r.max_ulp}};
  if (r.draw) j.update(json(*r.draw));
}
void to_json(json& j, const LodRow& r) {
  j = {{"scene", r.scene},
       {"samples", r.samples},
       {"device", r.device},
       {"repetitions", r.repetitions},
       {"coarser_by_haar_s", r.coarser_by_haar_s},
       {"coarser_by_reevaluation_s", r.coarser_by_reevaluation_s},
       {"finer_by_haar_s", r.finer_by_haar_s},
       {"finer_by_reevaluation_s", r.finer_by_reevaluation_s},
       {"levels", r.levels}};
  put_optional(j, "coarser_by_full_reevaluation_s", r.coarser_by_full_reevaluation_s);
  put_optional(j, "finer_by_full_reevaluation_s", r.finer_by_full_reevaluation_s);
  put_optional(j, "coarser_index_elements", r.coarser_index_elements);
  put_optional(j, "finer_index_elements", r.finer_index_elements);
  if (r.draw) j.update(json(*r.draw));
}
void to_json(json& j, const LodFile& f) {
  j = {{"format", kLodFileFormat},
       {"machine", f.machine},
       {"settings", f.settings},
       {"rows", f.rows}};
}
void to_json(json& j, const CameraCounts& c) {
  j = {{"draws", c.draws},
       {"passes", c.passes},
       {"host_read_backs", c.host_read_backs},
       {"device_copies", c.device_copies}};
}
void to_json(json& j, const CameraFrame& f) {
  j = {{"frame", f.frame},
       {"distance", f.distance},
       {"eye", f.eye},
       {"lod_grids", f.lod_grids},
       {"lod_samples", f.lod_samples},
       {"lod_triangles", f.lod_triangles},
       {"lod_frame_s", f.lod_frame_s},
       {"fixed_samples", f.fixed_samples},
       {"fixed_triangles", f.fixed_triangles},
       {"fixed_frame_s", f.fixed_frame_s}};
}
void to_json(json& j, const CameraPathRow& r) {
  j = {{"scene", r.scene},
       {"surfaces", r.surfaces},
       {"device", r.device},
       {"centre", r.centre},
       {"radius", r.radius},
       {"target", r.target},
       {"up", r.up},
       {"median_lod_frame_s", r.median_lod_frame_s},
       {"median_fixed_frame_s", r.median_fixed_frame_s},
       {"lod_counts", r.lod_counts},
       {"fixed_counts", r.fixed_counts},
       {"frames", r.frames}};
}
void to_json(json& j, const CameraPathFile& f) {
  j = {{"format", kCameraPathFileFormat},
       {"machine", f.machine},
       {"settings", f.settings},
       {"rows", f.rows}};
}
void to_json(json& j, const MemoryFileRow& r) {
  j = {{"scene", r.scene},
       {"surfaces", r.surfaces},
       {"ksquads", r.ksquads},
       {"bezier_patches", r.bezier_patches},
       {"nurbs_control_points", r.nurbs_control_points},
       {"nurbs_bytes", r.nurbs_bytes},
       {"bezier_control_points", r.bezier_control_points},
       {"bezier_bytes", r.bezier_bytes}};
  put_optional(j, "ratio", r.ratio);
  put_optional(j, "bezier_shared_control_points", r.bezier_shared_control_points);
  put_optional(j, "bezier_shared_bytes", r.bezier_shared_bytes);
  put_optional(j, "shared_ratio", r.shared_ratio);
}
void to_json(json& j, const MemoryFile& f) {
  j = f.notes;
  j["format"] = kMemoryFileFormat;
  j["rows"] = f.rows;
}

std::string CameraPathFile::fixed_samples() const {
  const auto it = settings.find("fixed_samples");
  return it != settings.end() && it->is_string() ? it->get<std::string>() : "n/a";
}

LodFile read_lod_file(const std::filesystem::path& path) {
  const json document = read_document(path, kLodFileFormat);
  const Fields top(path, document, "");
  LodFile file{object_or_empty(document, "machine"), object_or_empty(document, "settings"), {}};
  for (const Fields& r : top.list("rows")) {
    LodRow row;
    row.scene = r.text("scene");
    row.samples = r.text("samples");
    row.device = device_of(r);
    // Not read by the report; some hand-written files lack it.
    row.repetitions = r.has("repetitions") ? r.integer<int>("repetitions") : 0;
    row.coarser_by_haar_s = r.number("coarser_by_haar_s");
    row.coarser_by_reevaluation_s = r.number("coarser_by_reevaluation_s");
    row.finer_by_haar_s = r.number("finer_by_haar_s");
    row.finer_by_reevaluation_s = r.number("finer_by_reevaluation_s");
    row.coarser_by_full_reevaluation_s = r.optional_number("coarser_by_full_reevaluation_s");
    row.finer_by_full_reevaluation_s = r.optional_number("finer_by_full_reevaluation_s");
    row.coarser_index_elements = r.optional_integer<std::int64_t>("coarser_index_elements");
    row.finer_index_elements = r.optional_integer<std::int64_t>("finer_index_elements");
    row.draw = draw_of(r);
    for (const Fields& l : r.list("levels"))
      row.levels.push_back({l.integer<int>("level"), l.text("samples"), l.number("max_distance"),
                            l.number("max_ulp"), draw_of(l)});
    file.rows.push_back(std::move(row));
  }
  return file;
}

CameraPathFile read_camera_path_file(const std::filesystem::path& path) {
  const json document = read_document(path, kCameraPathFileFormat);
  const Fields top(path, document, "");
  CameraPathFile file{
      object_or_empty(document, "machine"), object_or_empty(document, "settings"), {}};
  for (const Fields& r : top.list("rows")) {
    CameraPathRow row;
    row.scene = r.text("scene");
    row.surfaces = r.integer<std::uint64_t>("surfaces");
    row.device = device_of(r);
    row.centre = r.point("centre");
    row.radius = r.number("radius");
    row.target = r.point("target");
    row.up = r.point("up");
    row.median_lod_frame_s = r.number("median_lod_frame_s");
    row.median_fixed_frame_s = r.number("median_fixed_frame_s");
    row.lod_counts = counts_of(r.child("lod_counts"));
    row.fixed_counts = counts_of(r.child("fixed_counts"));
    for (const Fields& f : r.list("frames")) {
      CameraFrame frame;
      frame.frame = f.integer<int>("frame");
      frame.distance = f.number("distance");
      frame.eye = f.point("eye");
      const json& grids = f.at("lod_grids");
      for (const json& g : grids) {
        if (!g.is_array() || g.size() != 2 || !g[0].is_number_integer() ||
            !g[1].is_number_integer())
          f.fail("lod_grids", grids, "must be a list of [nu, nv] integer pairs");
        frame.lod_grids.push_back({g[0].get<int>(), g[1].get<int>()});
      }
      frame.lod_samples = f.integer<std::uint64_t>("lod_samples");
      frame.lod_triangles = f.integer<std::uint64_t>("lod_triangles");
      frame.lod_frame_s = f.number("lod_frame_s");
      frame.fixed_samples = f.integer<std::uint64_t>("fixed_samples");
      frame.fixed_triangles = f.integer<std::uint64_t>("fixed_triangles");
      frame.fixed_frame_s = f.number("fixed_frame_s");
      row.frames.push_back(std::move(frame));
    }
    file.rows.push_back(std::move(row));
  }
  return file;
}

MemoryFile read_memory_file(const std::filesystem::path& path) {
  json document = read_document(path, kMemoryFileFormat);
  const Fields top(path, document, "");
  MemoryFile file;
  for (const Fields& r : top.list("rows")) {
    MemoryFileRow row;
    row.scene = r.text("scene");
    row.surfaces = r.integer<std::uint64_t>("surfaces");
    row.ksquads = r.integer<std::uint64_t>("ksquads");
    row.bezier_patches = r.integer<std::uint64_t>("bezier_patches");
    row.nurbs_control_points = r.integer<std::uint64_t>("nurbs_control_points");
    row.nurbs_bytes = r.integer<std::uint64_t>("nurbs_bytes");
    row.bezier_control_points = r.integer<std::uint64_t>("bezier_control_points");
    row.bezier_bytes = r.integer<std::uint64_t>("bezier_bytes");
    row.ratio = r.optional_number("ratio");
    row.bezier_shared_control_points =
        r.optional_integer<std::uint64_t>("bezier_shared_control_points");
    row.bezier_shared_bytes = r.optional_integer<std::uint64_t>("bezier_shared_bytes");
    row.shared_ratio = r.optional_number("shared_ratio");
    file.rows.push_back(std::move(row));
  }
  document.erase("rows");
  document.erase("format");
  file.notes = std::move(document);
  return file;
}

}  // namespace nurbs
