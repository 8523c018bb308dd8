// The scene loader (nurbs-scene/1 and /2, trims and T-splines included) through its public API: a
// parsed scene passes validate_scene and reads back from scene_to_json bit-identically; anything
// else it refuses with InputError.
#include <bit>
#include <cstdint>
#include <string_view>

#include "fuzz_check.h"
#include "reference/tspline.h"
#include "scenes/scene_json.h"

namespace nurbs::fuzz {
namespace {

constexpr std::string_view kOrigin = "fuzz.json";

bool same(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

template <typename T>
bool same_numbers(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if constexpr (std::is_same_v<T, double>) {
      if (!same(a[k], b[k])) return false;
    } else {
      for (std::size_t c = 0; c < a[k].size(); ++c)
        if (!same(a[k][c], b[k][c])) return false;
    }
  }
  return true;
}

bool same_trim(const std::optional<Trim>& a, const std::optional<Trim>& b) {
  if (a.has_value() != b.has_value()) return false;
  if (!a) return true;
  if (a->rule != b->rule || !same(a->tolerance, b->tolerance) || a->loops.size() != b->loops.size())
    return false;
  for (std::size_t l = 0; l < a->loops.size(); ++l) {
    const auto &ca = a->loops[l].curves, &cb = b->loops[l].curves;
    if (ca.size() != cb.size()) return false;
    for (std::size_t c = 0; c < ca.size(); ++c)
      if (ca[c].degree != cb[c].degree || !same_numbers(ca[c].knots, cb[c].knots) ||
          !same_numbers(ca[c].points, cb[c].points) || !same_numbers(ca[c].weights, cb[c].weights))
        return false;
  }
  return true;
}

void check_same_scene(const Scene& a, const Scene& b) {
  check(a.name == b.name && a.description == b.description, "name/description changed");
  check(a.surfaces.size() == b.surfaces.size(), "surface count changed");
  for (std::size_t i = 0; i < a.surfaces.size(); ++i) {
    const Surface &s = a.surfaces[i], &t = b.surfaces[i];
    check(s.name == t.name && s.degree_u == t.degree_u && s.degree_v == t.degree_v &&
              s.count_u == t.count_u && s.count_v == t.count_v,
          "surface header changed", s.name);
    check(same_numbers(s.knots_u, t.knots_u) && same_numbers(s.knots_v, t.knots_v), "knots changed",
          s.name);
    check(same_numbers(s.points, t.points) && same_numbers(s.weights, t.weights),
          "control net changed", s.name);
    check(same_trim(s.trim, t.trim), "trim changed", s.name);
    check(s.reversed == t.reversed, "orientation changed", s.name);
    check(s.is_tspline() == t.is_tspline(), "kind changed", s.name);
    if (!s.is_tspline()) continue;
    const TSplineSurface &x = *s.tspline, &y = *t.tspline;
    check(x.name == y.name && x.degree_u == y.degree_u && x.degree_v == y.degree_v &&
              same(x.u_min, y.u_min) && same(x.u_max, y.u_max) && same(x.v_min, y.v_min) &&
              same(x.v_max, y.v_max),
          "T-spline header changed", s.name);
    check(same_numbers(x.points, y.points) && same_numbers(x.weights, y.weights) &&
              same_numbers(x.knots_u, y.knots_u) && same_numbers(x.knots_v, y.knots_v),
          "T-spline changed", s.name);
  }
}

}  // namespace
}  // namespace nurbs::fuzz

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace nurbs;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  Scene scene;
  try {
    scene = parse_scene_json(text, fuzz::kOrigin);
  } catch (const InputError& e) {
    fuzz::check_error_line(e, fuzz::kOrigin);
    return 0;
  }
  try {
    validate_scene(scene, fuzz::kOrigin);
    const std::string written = scene_to_json(scene);
    fuzz::check_same_scene(scene, parse_scene_json(written, "written.json"));
  } catch (const InputError& e) {
    fuzz::finding("a scene the reader accepted is refused after writing it", e.what());
  }
  return 0;
}
