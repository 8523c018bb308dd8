#include "scenes/scene_json.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <span>

#include "reference/error_text.h"
#include "reference/surface_checker.h"
#include "reference/tspline.h"
#include "reference/validation.h"
#include "scenes/json_strict.h"

namespace nurbs {
namespace {

using nlohmann::json;

std::string describe(const json& value) {
  std::string text = value.dump();
  if (text.size() > 40) text = text.substr(0, 37) + "...";
  return text;
}

bool is_real(const json& v) {
  return v.is_number() && !v.is_boolean();
}

// The fields of one JSON object of a surface (the surface itself, its trim, a loop, a curve),
// each error naming the field by its path from the surface ("trim.loops[0].curves[2].knots").
class ObjectReader {
 public:
  // `path` is "" for the surface object itself.
  ObjectReader(const json& object, std::string path, const SurfaceChecker& check)
      : object_(object), path_(std::move(path)), check_(check) {}

  // Element `index` of the array at `array_path`, which must be an object.
  static ObjectReader element(const json& array, const std::string& array_path, std::size_t index,
                              const SurfaceChecker& check, std::string_view rule) {
    const json& object = array[index];
    if (!object.is_object())
      check.fail(array_path, std::to_string(index), describe(object), std::string(rule));
    return ObjectReader(object, fmt::format("{}[{}]", array_path, index), check);
  }

  std::string field(std::string_view key) const {
    return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
  }

  [[noreturn]] void fail(std::string_view key, const std::string& index, const std::string& value,
                         const std::string& rule) const {
    check_.fail(field(key), index, value, rule);
  }

  void refuse_unknown_keys(std::span<const std::string_view> known) const {
    for (const auto& [key, value] : object_.items())
      if (std::find(known.begin(), known.end(), key) == known.end())
        fail(key, "", describe(value),
             fmt::format("unknown key (expected {})", fmt::join(known, ", ")));
  }

  const json* optional(const char* key) const {
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }

  const json& required(const char* key) const {
    if (const json* value = optional(key)) return *value;
    fail(key, "", "(missing)", "required field is missing");
  }

  int integer(const char* key) const {
    const json& value = required(key);
    if (!value.is_number_integer()) fail(key, "", describe(value), "must be an integer");
    const auto wide = value.is_number_unsigned()
                          ? static_cast<long double>(value.get<std::uint64_t>())
                          : static_cast<long double>(value.get<std::int64_t>());
    if (wide < -1e9L || wide > 1e9L) fail(key, "", describe(value), "out of range");
    return static_cast<int>(wide);
  }

  double number(const char* key) const {
    const json& value = required(key);
    if (!is_real(value)) fail(key, "", describe(value), "must be a number");
    return value.get<double>();
  }

  std::string string(const char* key) const {
    const json& value = required(key);
    if (!value.is_string()) fail(key, "", describe(value), "must be a string");
    return value.get<std::string>();
  }

  // An array of at most `max` entries (checked before anything is allocated for it).
  const json& array(const char* key, std::string_view what, std::size_t max) const {
    const json& value = required(key);
    if (!value.is_array())
      fail(key, "", describe(value), fmt::format("must be an array of {}", what));
    check_.check_at_most(field(key), value.size(), max, what);
    return value;
  }

  std::vector<double> numbers(const char* key, std::size_t max) const {
    const json& value = array(key, "numbers", max);
    std::vector<double> out;
    out.reserve(value.size());
    for (std::size_t k = 0; k < value.size(); ++k) {
      if (!is_real(value[k])) fail(key, std::to_string(k), describe(value[k]), "must be a number");
      out.push_back(value[k].get<double>());
    }
    return out;
  }

  // Entries of `value` (the array at `key`), each an array of N numbers written as `shape`.
  template <std::size_t N>
  std::vector<std::array<double, N>> tuples(const char* key, const json& value,
                                            std::string_view shape) const {
    std::vector<std::array<double, N>> out(value.size());
    for (std::size_t k = 0; k < value.size(); ++k) {
      const json& p = value[k];
      if (!p.is_array() || p.size() != N || !std::all_of(p.begin(), p.end(), is_real))
        fail(key, std::to_string(k), describe(p), fmt::format("must be {} numbers", shape));
      for (std::size_t c = 0; c < N; ++c) out[k][c] = p[c].get<double>();
    }
    return out;
  }

 private:
  const json& object_;
  std::string path_;
  const SurfaceChecker& check_;
};

// The longest knot vectors a valid surface direction or trim curve can have: a longer array is
// refused before it is copied.
constexpr std::size_t kMaxKnots = kMaxCountPerDirection + kMaxDegree + 1;
constexpr std::size_t kMaxTrimKnots = kMaxTrimPointsPerCurve + kMaxDegree + 1;

TrimCurve read_trim_curve(const ObjectReader& r) {
  static constexpr std::string_view kKeys[] = {"degree", "knots", "points", "weights"};
  r.refuse_unknown_keys(kKeys);
  TrimCurve curve;
  curve.degree = r.integer("degree");
  curve.knots = r.numbers("knots", kMaxTrimKnots);
  curve.points = r.tuples<2>(
      "points", r.array("points", "[u, v] control points", kMaxTrimPointsPerCurve), "[u, v]");
  if (r.optional("weights"))
    curve.weights = r.numbers("weights", kMaxTrimPointsPerCurve);
  else
    curve.weights.assign(curve.points.size(), 1.0);
  return curve;
}

Trim read_trim(const json& value, const SurfaceChecker& check) {
  if (!value.is_object())
    check.fail("trim", "", describe(value),
               "must be an object {\"rule\", \"tolerance\", \"loops\"}");
  const ObjectReader r(value, "trim", check);
  static constexpr std::string_view kKeys[] = {"rule", "tolerance", "loops"};
  r.refuse_unknown_keys(kKeys);
  Trim trim;
  if (r.optional("rule")) trim.rule = r.string("rule");
  if (r.optional("tolerance")) trim.tolerance = r.number("tolerance");
  const json& loops = r.array("loops", "loops", kMaxTrimLoops);
  trim.loops.reserve(loops.size());
  for (std::size_t l = 0; l < loops.size(); ++l) {
    const ObjectReader loop = ObjectReader::element(loops, r.field("loops"), l, check,
                                                    "a loop must be an object {\"curves\": [...]}");
    static constexpr std::string_view kLoopKeys[] = {"curves"};
    loop.refuse_unknown_keys(kLoopKeys);
    const json& curves = loop.array("curves", "curves", kMaxTrimCurvesPerLoop);
    TrimLoop& out = trim.loops.emplace_back();
    out.curves.reserve(curves.size());
    for (std::size_t c = 0; c < curves.size(); ++c)
      out.curves.push_back(read_trim_curve(ObjectReader::element(
          curves, loop.field("curves"), c, check, "a trim curve must be a JSON object")));
  }
  return trim;
}

// Reads one surface object, naming the surface, field and index of anything malformed.
class SurfaceReader {
 public:
  SurfaceReader(const json& object, int index, std::string_view origin, bool version2)
      : object_(object),
        index_(index),
        origin_(origin),
        version2_(version2),
        check_(surface_, index, origin) {}

  Surface read() {
    if (!object_.is_object())
      check_.fail("surfaces", std::to_string(index_), describe(object_),
                  "a surface must be a JSON object");
    const ObjectReader r(object_, "", check_);
    if (r.optional("name"))
      surface_.name = r.string("name");
    else
      surface_.name = fmt::format("surface{}", index_);
    for (const char* key : {"trim", "orientation", "kind"})
      if (!version2_ && r.optional(key))
        r.fail(
            key, "", describe(*r.optional(key)),
            fmt::format("needs \"format\": \"{}\" (this file is {})", kSceneFormat2, kSceneFormat));
    if (r.optional("kind")) {
      const std::string kind = r.string("kind");
      if (kind == "t-spline") return read_tspline(r);
      if (kind != "nurbs")
        r.fail("kind", "", describe(*r.optional("kind")), "must be \"nurbs\" or \"t-spline\"");
    }
    // nurbs-scene/2 adds the last three.
    static constexpr std::string_view kKeys[] = {"name",    "degree_u",    "degree_v", "count_u",
                                                 "count_v", "knots_u",     "knots_v",  "points",
                                                 "weights", "orientation", "trim",     "kind"};
    r.refuse_unknown_keys(version2_ ? std::span(kKeys) : std::span(kKeys).first(9));

    surface_.degree_u = r.integer("degree_u");
    surface_.degree_v = r.integer("degree_v");
    surface_.count_u = r.integer("count_u");
    surface_.count_v = r.integer("count_v");
    validate_surface_sizes(surface_, index_, origin_);  // before anything is allocated

    surface_.knots_u = r.numbers("knots_u", kMaxKnots);
    surface_.knots_v = r.numbers("knots_v", kMaxKnots);
    const std::size_t expected = static_cast<std::size_t>(surface_.count_u) * surface_.count_v;
    const json& points = r.array("points", "[x, y, z] control points", kMaxControlPointsPerSurface);
    if (points.size() != expected)
      r.fail("points", kLengthIndex, std::to_string(points.size()),
             fmt::format("need count_u * count_v = {} points", expected));
    surface_.points = r.tuples<3>("points", points, "[x, y, z]");
    if (r.optional("weights")) {
      surface_.weights = r.numbers("weights", kMaxControlPointsPerSurface);
      if (surface_.weights.size() != expected)
        r.fail("weights", kLengthIndex, std::to_string(surface_.weights.size()),
               fmt::format("need count_u * count_v = {} weights", expected));
    } else {
      surface_.weights.assign(expected, 1.0);
    }
    if (r.optional("orientation")) {
      const std::string orientation = r.string("orientation");
      if (orientation != "forward" && orientation != "reversed")
        r.fail("orientation", "", describe(*r.optional("orientation")),
               "must be \"forward\" or \"reversed\"");
      surface_.reversed = orientation == "reversed";
    }
    if (const json* trim = r.optional("trim")) surface_.trim = read_trim(*trim, check_);
    return std::move(surface_);
  }

 private:
  // "kind": "t-spline" (nurbs-scene/2): the point-based form of reference/tspline.h, one local
  // knot vector of degree+2 knots per control point in each direction ("knots_u": [[...], ...]),
  // and the domain [u_min, u_max, v_min, v_max]. The rules are validate_tspline's (checked when
  // the scene is); the sizes are checked here, before anything is allocated.
  Surface read_tspline(const ObjectReader& r) {
    static constexpr std::string_view kKeys[] = {"name",     "kind",    "degree_u",
                                                 "degree_v", "domain",  "points",
                                                 "weights",  "knots_u", "knots_v"};
    r.refuse_unknown_keys(kKeys);
    TSplineSurface t;
    t.name = surface_.name;
    t.degree_u = surface_.degree_u = r.integer("degree_u");
    t.degree_v = surface_.degree_v = r.integer("degree_v");
    check_.check_degree("degree_u", t.degree_u);
    check_.check_degree("degree_v", t.degree_v);
    const std::vector<double> domain = r.numbers("domain", 4);
    if (domain.size() != 4)
      r.fail("domain", kLengthIndex, std::to_string(domain.size()),
             "must be [u_min, u_max, v_min, v_max]");
    t.u_min = domain[0];
    t.u_max = domain[1];
    t.v_min = domain[2];
    t.v_max = domain[3];
    const json& points = r.array("points", "[x, y, z] control points",
                                 static_cast<std::size_t>(kMaxTSplineControlPoints));
    t.points = r.tuples<3>("points", points, "[x, y, z]");
    if (r.optional("weights")) {
      t.weights = r.numbers("weights", points.size());
      if (t.weights.size() != points.size())
        r.fail("weights", kLengthIndex, std::to_string(t.weights.size()),
               fmt::format("need one weight per point ({})", points.size()));
    } else {
      t.weights.assign(points.size(), 1.0);
    }
    t.knots_u = local_knot_vectors(r, "knots_u", points.size(), t.degree_u);
    t.knots_v = local_knot_vectors(r, "knots_v", points.size(), t.degree_v);
    check_domain_covered(r, domain, t.knots_u, t.degree_u, 0, "u");
    check_domain_covered(r, domain, t.knots_v, t.degree_v, 2, "v");
    return make_tspline_surface(std::move(t));
  }

  // Outside every point's support the blending functions' sum is 0 and S(u, v) = 0/0: a domain
  // reaching past the span of the local knot vectors would be evaluated to NaN there. Refused at
  // load, naming the end and the span (validate_tspline checks the rest of the domain's rules).
  void check_domain_covered(const ObjectReader& r, const std::vector<double>& domain,
                            const std::vector<double>& knots, int degree, std::size_t first,
                            const char* direction) const {
    const std::size_t n = static_cast<std::size_t>(degree) + 2;
    if (knots.empty()) return;
    double low = knots[0], high = knots[n - 1];
    for (std::size_t k = 0; k + n <= knots.size(); k += n) {
      low = std::min(low, knots[k]);
      high = std::max(high, knots[k + n - 1]);
    }
    const auto fail = [&](std::size_t index) {
      r.fail("domain", std::to_string(index), fmt::format("{:g}", domain[index]),
             fmt::format("the domain must lie within [{:g}, {:g}], where the local knot vectors "
                         "give {} a blending function (outside, S(u, v) is 0/0)",
                         low, high, direction));
    };
    // !(a >= b): a NaN end is refused here too.
    if (!(domain[first] >= low)) fail(first);
    if (!(domain[first + 1] <= high)) fail(first + 1);
  }

  // One array of degree+2 knots per point, concatenated.
  std::vector<double> local_knot_vectors(const ObjectReader& r, const char* key, std::size_t count,
                                         int degree) const {
    const json& vectors = r.array(key, "local knot vectors, one per point", count);
    if (vectors.size() != count)
      r.fail(key, kLengthIndex, std::to_string(vectors.size()),
             fmt::format("need one local knot vector per point ({})", count));
    const std::size_t n = static_cast<std::size_t>(degree) + 2;
    std::vector<double> knots;
    knots.reserve(count * n);
    for (std::size_t k = 0; k < count; ++k) {
      const json& local = vectors[k];
      if (!local.is_array() || local.size() != n)
        r.fail(key, std::to_string(k), describe(local),
               fmt::format("must be degree + 2 = {} knots", n));
      for (std::size_t i = 0; i < n; ++i) {
        if (!is_real(local[i]))
          r.fail(key, fmt::format("{}][{}", k, i), describe(local[i]), "must be a number");
        knots.push_back(local[i].get<double>());
      }
    }
    return knots;
  }

  const json& object_;
  int index_;
  std::string_view origin_;
  bool version2_;
  Surface surface_;
  SurfaceChecker check_;
};

[[noreturn]] void fail_scene(std::string_view origin, const std::string& field,
                             const std::string& value, const std::string& rule) {
  throw InputError(fmt::format("{}: {} = {}: {}", printable(origin),
                               printable(field, kQuotedValueBytes), printable(value), rule));
}

}  // namespace

Scene parse_scene_json(std::string_view text, std::string_view origin) {
  const json document = parse_json_strictly(text, origin);
  if (!document.is_object())
    fail_scene(origin, "(document)", describe(document), "must be a JSON object");
  for (const auto& [key, value] : document.items())
    if (key != "format" && key != "name" && key != "description" && key != "surfaces")
      fail_scene(origin, key, describe(value),
                 "unknown key (expected format, name, description, surfaces)");
  const auto format = document.find("format");
  if (format == document.end() || (*format != kSceneFormat && *format != kSceneFormat2))
    fail_scene(origin, "format", format != document.end() ? describe(*format) : "(missing)",
               fmt::format("must be \"{}\" or \"{}\"", kSceneFormat, kSceneFormat2));
  const bool version2 = *format == kSceneFormat2;
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
    scene.surfaces.push_back(
        SurfaceReader(surfaces[i], static_cast<int>(i), origin, version2).read());
  validate_scene(scene, origin);
  return scene;
}

std::string read_input_file(const std::filesystem::path& path, std::string_view kind) {
  std::error_code error;
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error)
    throw InputError(fmt::format("{}: cannot read {} file: {}", printable(path.string()), kind,
                                 error.message()));
  if (size > kMaxSceneFileBytes)
    throw InputError(
        fmt::format("{}: file size {} bytes exceeds the limit of {} bytes for a {} "
                    "file",
                    printable(path.string()), size, kMaxSceneFileBytes, kind));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open {} file", printable(path.string()), kind));
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  return bytes;
}

nlohmann::json read_json_strictly(const std::filesystem::path& path, std::string_view kind) {
  return parse_json_strictly(read_input_file(path, kind), path.string());
}

Scene load_scene_file(const std::filesystem::path& path) {
  Scene scene = parse_scene_json(read_input_file(path, "scene"), path.string());
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

bool all_one(const std::vector<double>& weights) {
  return std::all_of(weights.begin(), weights.end(), [](double w) { return w == 1.0; });
}

// One control point per line at `indent`, as "[a, b, ...]".
template <typename Point>
std::string point_lines(const std::vector<Point>& points, std::string_view indent) {
  std::string out;
  for (std::size_t k = 0; k < points.size(); ++k)
    out += fmt::format("{}\n{}[{}]", k ? "," : "", indent, join_numbers(points[k]));
  return out;
}

std::string trim_json(const Trim& trim) {
  std::string out = fmt::format(
      ",\n      \"trim\": {{\n        \"rule\": {}, \"tolerance\": {},\n        \"loops\": [",
      json(trim.rule).dump(), number_text(trim.tolerance));
  for (std::size_t l = 0; l < trim.loops.size(); ++l) {
    out += fmt::format("{}\n          {{\n            \"curves\": [", l ? "," : "");
    const std::vector<TrimCurve>& curves = trim.loops[l].curves;
    for (std::size_t c = 0; c < curves.size(); ++c) {
      const TrimCurve& curve = curves[c];
      out += fmt::format(
          "{}\n              {{\n                \"degree\": {},\n                \"knots\": "
          "[{}],\n"
          "                \"points\": [{}\n                ]",
          c ? "," : "", curve.degree, join_numbers(curve.knots),
          point_lines(curve.points, "                  "));
      if (!all_one(curve.weights))
        out += fmt::format(",\n                \"weights\": [{}]", join_numbers(curve.weights));
      out += "\n              }";
    }
    out += "\n            ]\n          }";
  }
  out += "\n        ]\n      }";
  return out;
}

// One local knot vector per line, like the points.
std::string local_knot_lines(const std::vector<double>& knots, int degree) {
  const std::size_t n = static_cast<std::size_t>(degree) + 2;
  std::string out;
  for (std::size_t k = 0; k < knots.size() / n; ++k)
    out += fmt::format("{}\n        [{}]", k ? "," : "",
                       join_numbers(std::span(knots).subspan(k * n, n)));
  return out;
}

std::string tspline_json(const TSplineSurface& t) {
  std::string out = fmt::format(
      "\n    {{\n      \"name\": {},\n      \"kind\": \"t-spline\",\n      \"degree_u\": {}, "
      "\"degree_v\": {},\n      \"domain\": [{}, {}, {}, {}],\n      \"points\": [{}\n      ]",
      json(t.name).dump(), t.degree_u, t.degree_v, number_text(t.u_min), number_text(t.u_max),
      number_text(t.v_min), number_text(t.v_max), point_lines(t.points, "        "));
  if (!all_one(t.weights))
    out += fmt::format(",\n      \"weights\": [{}]", join_numbers(t.weights));
  out +=
      fmt::format(",\n      \"knots_u\": [{}\n      ],\n      \"knots_v\": [{}\n      ]\n    }}",
                  local_knot_lines(t.knots_u, t.degree_u), local_knot_lines(t.knots_v, t.degree_v));
  return out;
}
}  // namespace

std::string scene_to_json(const Scene& scene) {
  // Written by hand rather than json::dump so a control point is one line: files stay readable
  // and diffable. fmt's "{}" prints doubles in shortest round-trip form. A scene /1 can hold is
  // written as /1, so files of untrimmed scenes stay what older readers accept.
  const bool version2 = std::any_of(
      scene.surfaces.begin(), scene.surfaces.end(),
      [](const Surface& s) { return s.trim.has_value() || s.reversed || s.is_tspline(); });
  std::string out = fmt::format(
      "{{\n  \"format\": \"{}\",\n  \"name\": {},\n  \"description\": {},\n  \"surfaces\": [",
      version2 ? kSceneFormat2 : kSceneFormat, json(scene.name).dump(),
      json(scene.description).dump());
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    if (s.is_tspline()) {
      if (i) out += ",";
      out += tspline_json(*s.tspline);
      continue;
    }
    out += fmt::format(
        "{}\n    {{\n      \"name\": {},\n      \"degree_u\": {}, \"degree_v\": {},\n"
        "      \"count_u\": {}, \"count_v\": {},\n      \"knots_u\": [{}],\n      \"knots_v\": "
        "[{}],\n"
        "      \"points\": [{}\n      ]",
        i ? "," : "", json(s.name).dump(), s.degree_u, s.degree_v, s.count_u, s.count_v,
        join_numbers(s.knots_u), join_numbers(s.knots_v), point_lines(s.points, "        "));
    if (s.is_rational()) out += fmt::format(",\n      \"weights\": [{}]", join_numbers(s.weights));
    if (s.reversed) out += ",\n      \"orientation\": \"reversed\"";
    if (s.trim) out += trim_json(*s.trim);
    out += "\n    }";
  }
  out += "\n  ]\n}\n";
  return out;
}

}  // namespace nurbs
