#include "scenes/scene_json.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "reference/validation.h"
#include "scenes/json_error.h"

namespace nurbs {
namespace {

using nlohmann::json;

std::string describe(const json& value) {
  std::string text = value.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

// Reads one surface object, naming the surface, field and index of anything malformed.
class SurfaceReader {
 public:
  SurfaceReader(const json& object, int index, std::string_view origin)
      : object_(object), index_(index), origin_(origin) {}

  Surface read() {
    if (!object_.is_object())
      throw ValidationError(std::string(origin_), "", index_, "surfaces", std::to_string(index_),
                            describe(object_), "a surface must be a JSON object");
    static const char* known[] = {"name",    "degree_u", "degree_v", "count_u", "count_v",
                                  "knots_u", "knots_v",  "points",   "weights"};
    if (object_.contains("name") && object_["name"].is_string())
      surface_.name = object_["name"].get<std::string>();
    else if (object_.contains("name"))
      fail("name", "", describe(object_["name"]), "must be a string");
    else
      surface_.name = fmt::format("surface{}", index_);
    for (const auto& [key, value] : object_.items())
      if (std::find(std::begin(known), std::end(known), key) == std::end(known))
        fail(key, "", describe(value),
             "unknown key (expected name, degree_u, degree_v, count_u, count_v, knots_u, "
             "knots_v, points, weights)");

    surface_.degree_u = integer("degree_u");
    surface_.degree_v = integer("degree_v");
    surface_.count_u = integer("count_u");
    surface_.count_v = integer("count_v");
    validate_surface_sizes(surface_, index_, origin_);  // before anything is allocated

    surface_.knots_u = numbers("knots_u");
    surface_.knots_v = numbers("knots_v");
    read_points();
    read_weights();
    return std::move(surface_);
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& index,
                         const std::string& value, const std::string& rule) const {
    throw ValidationError(std::string(origin_), surface_.name, index_, field, index, value, rule);
  }

  const json& required(const char* field) const {
    if (!object_.contains(field)) fail(field, "", "(missing)", "required field is missing");
    return object_[field];
  }

  int integer(const char* field) const {
    const json& value = required(field);
    if (!value.is_number_integer()) fail(field, "", describe(value), "must be an integer");
    const auto wide = value.is_number_unsigned()
                          ? static_cast<long double>(value.get<std::uint64_t>())
                          : static_cast<long double>(value.get<std::int64_t>());
    if (wide < -1e9L || wide > 1e9L) fail(field, "", describe(value), "out of range");
    return static_cast<int>(wide);
  }

  static bool is_real(const json& v) { return v.is_number() && !v.is_boolean(); }

  std::vector<double> numbers(const char* field) const {
    const json& value = required(field);
    if (!value.is_array()) fail(field, "", describe(value), "must be an array of numbers");
    std::vector<double> out;
    out.reserve(value.size());
    for (std::size_t k = 0; k < value.size(); ++k) {
      if (!is_real(value[k]))
        fail(field, std::to_string(k), describe(value[k]), "must be a number");
      out.push_back(value[k].get<double>());
    }
    return out;
  }

  std::size_t expected_points() const {
    return static_cast<std::size_t>(surface_.count_u) * surface_.count_v;
  }

  void read_points() {
    const json& value = required("points");
    if (!value.is_array()) fail("points", "", describe(value), "must be an array of [x, y, z]");
    if (value.size() != expected_points())
      fail("points", kLengthIndex, std::to_string(value.size()),
           fmt::format("need count_u * count_v = {} points", expected_points()));
    surface_.points.resize(value.size());
    for (std::size_t k = 0; k < value.size(); ++k) {
      const json& p = value[k];
      if (!p.is_array() || p.size() != 3 || !is_real(p[0]) || !is_real(p[1]) || !is_real(p[2]))
        fail("points", std::to_string(k), describe(p), "must be [x, y, z] numbers");
      surface_.points[k] = {p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
    }
  }

  void read_weights() {
    if (!object_.contains("weights")) {
      surface_.weights.assign(expected_points(), 1.0);
      return;
    }
    surface_.weights = numbers("weights");
    if (surface_.weights.size() != expected_points())
      fail("weights", kLengthIndex, std::to_string(surface_.weights.size()),
           fmt::format("need count_u * count_v = {} weights", expected_points()));
  }

  const json& object_;
  int index_;
  std::string_view origin_;
  Surface surface_;
};

[[noreturn]] void fail_scene(std::string_view origin, const std::string& field,
                             const std::string& value, const std::string& rule) {
  throw InputError(fmt::format("{}: {} = {}: {}", origin, field, value, rule));
}

}  // namespace

Scene parse_scene_json(std::string_view text, std::string_view origin) {
  json document;
  try {
    document = json::parse(text.begin(), text.end());
  } catch (const json::exception& e) {  // parse_error, and out_of_range for 1e999
    throw InputError(fmt::format("{}: not valid JSON: {}", origin, json_error_text(e)));
  }
  if (!document.is_object())
    fail_scene(origin, "(document)", describe(document), "must be a JSON object");
  for (const auto& [key, value] : document.items())
    if (key != "format" && key != "name" && key != "description" && key != "surfaces")
      fail_scene(origin, key, describe(value),
                 "unknown key (expected format, name, description, surfaces)");
  if (!document.contains("format") || document["format"] != kSceneFormat)
    fail_scene(origin, "format",
               document.contains("format") ? describe(document["format"]) : "(missing)",
               fmt::format("must be \"{}\"", kSceneFormat));
  Scene scene;
  if (document.contains("name")) {
    if (!document["name"].is_string())
      fail_scene(origin, "name", describe(document["name"]), "must be a string");
    scene.name = document["name"].get<std::string>();
  }
  if (document.contains("description")) {
    if (!document["description"].is_string())
      fail_scene(origin, "description", describe(document["description"]), "must be a string");
    scene.description = document["description"].get<std::string>();
  }
  if (!document.contains("surfaces") || !document["surfaces"].is_array())
    fail_scene(origin, "surfaces",
               document.contains("surfaces") ? describe(document["surfaces"]) : "(missing)",
               "must be an array of surfaces");
  const json& surfaces = document["surfaces"];
  if (surfaces.size() > static_cast<std::size_t>(kMaxSurfacesPerScene))
    fail_scene(origin, "surfaces", fmt::format("({} entries)", surfaces.size()),
               fmt::format("at most {} surfaces", kMaxSurfacesPerScene));
  scene.surfaces.reserve(surfaces.size());
  for (std::size_t i = 0; i < surfaces.size(); ++i)
    scene.surfaces.push_back(SurfaceReader(surfaces[i], static_cast<int>(i), origin).read());
  validate_scene(scene, origin);
  return scene;
}

Scene load_scene_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open scene file", path.string()));
  std::ostringstream text;
  text << in.rdbuf();
  Scene scene = parse_scene_json(text.str(), path.string());
  if (scene.name.empty()) scene.name = path.stem().string();
  return scene;
}

namespace {
// fmt's shortest round-trip form, except that -0.0 must not read back as the integer 0 (+0.0).
std::string number_text(double x) {
  return x == 0 && std::signbit(x) ? "-0.0" : fmt::format("{}", x);
}

template <typename Range>
std::string join_numbers(const Range& values) {
  std::string out;
  for (double x : values) {
    if (!out.empty()) out += ", ";
    out += number_text(x);
  }
  return out;
}
}  // namespace

std::string scene_to_json(const Scene& scene) {
  // Written by hand rather than json::dump so a control point is one line: files stay readable
  // and diffable. fmt's "{}" prints doubles in shortest round-trip form.
  std::string out = fmt::format(
      "{{\n  \"format\": \"{}\",\n  \"name\": {},\n  \"description\": {},\n  \"surfaces\": [",
      kSceneFormat, json(scene.name).dump(), json(scene.description).dump());
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    out += fmt::format(
        "{}\n    {{\n      \"name\": {},\n      \"degree_u\": {}, \"degree_v\": {},\n"
        "      \"count_u\": {}, \"count_v\": {},\n      \"knots_u\": [{}],\n      \"knots_v\": "
        "[{}],\n"
        "      \"points\": [",
        i ? "," : "", json(s.name).dump(), s.degree_u, s.degree_v, s.count_u, s.count_v,
        join_numbers(s.knots_u), join_numbers(s.knots_v));
    for (std::size_t k = 0; k < s.points.size(); ++k)
      out += fmt::format("{}\n        [{}]", k ? "," : "", join_numbers(s.points[k]));
    out += "\n      ]";
    if (s.is_rational()) out += fmt::format(",\n      \"weights\": [{}]", join_numbers(s.weights));
    out += "\n    }";
  }
  out += "\n  ]\n}\n";
  return out;
}

}  // namespace nurbs
