// The scene the --uv reader is fuzzed and unit-tested against: surface 0 "patch" on [0, 1]^2 and
// surface 1 on [-2, 3.5] x [1, 2] named "0", a name that reads as the other's index -- so the
// name-before-index rule and both domains' range checks are reachable. Bilinear: the reader only
// reads domains.
#pragma once

#include "reference/validation.h"
#include "tests/harness/plates.h"

namespace nurbs::fuzz {

inline const Scene& uv_test_scene() {
  static const Scene scene = [] {
    Scene s;
    s.name = "uv-test";
    s.surfaces = {test::bilinear_patch("patch", {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 1}),
                  test::bilinear_patch("0", {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 1})};
    s.surfaces[1].knots_u = {-2, -2, 3.5, 3.5};
    s.surfaces[1].knots_v = {1, 1, 2, 2};
    validate_scene(s, "uv test scene");
    return s;
  }();
  return scene;
}

}  // namespace nurbs::fuzz
