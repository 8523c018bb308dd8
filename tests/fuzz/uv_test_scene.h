// The scene the --uv reader is fuzzed and unit-tested against: surface 0 "patch" on [0, 1]^2 and
// surface 1 on [-2, 3.5] x [1, 2] named "0", a name that reads as the other's index -- so the
// name-before-index rule and both domains' range checks are reachable. Bilinear: the reader only
// reads domains.
#pragma once

#include <string>

#include "reference/validation.h"

namespace nurbs::fuzz {

inline Surface bilinear_patch(std::string name, double u0, double u1, double v0, double v1) {
  Surface s;
  s.name = std::move(name);
  s.degree_u = s.degree_v = 1;
  s.count_u = s.count_v = 2;
  s.knots_u = {u0, u0, u1, u1};
  s.knots_v = {v0, v0, v1, v1};
  s.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 1}};
  s.weights = {1, 1, 1, 1};
  return s;
}

inline const Scene& uv_test_scene() {
  static const Scene scene = [] {
    Scene s;
    s.name = "uv-test";
    s.surfaces = {bilinear_patch("patch", 0, 1, 0, 1), bilinear_patch("0", -2, 3.5, 1, 2)};
    validate_scene(s, "uv test scene");
    return s;
  }();
  return scene;
}

}  // namespace nurbs::fuzz
