// The built-in `many-ducks-N` scenes: 000's Fig 8 workload with its trims -- N copies of the duck
// (scenes/data/duck.json, 3 rational surfaces) side by side on a square grid, one third of them
// trimmed. Ducks 0, 3, 6, ... (index % 3 == 0, so every N has at least one trimmed duck and
// ceil(N / 3) in all) have each of their 3 surfaces trimmed to the trimmed plate's loops
// (scenes/trimmed_plate.h: a rounded rectangle of lines and rational quarter circles with a
// circular hole) mapped affinely onto that surface's (u, v) domain: exact rational curves, whose
// inside is a known fraction of each domain.
#pragma once

#include "reference/surface.h"

namespace nurbs {

inline constexpr int kMaxManyDucks = 1024;

// `duck` is the built-in duck; the result is named "many-ducks-N", its surfaces "duck<k>.<name>".
Scene many_ducks_scene(const Scene& duck, int n);

// Whether duck k of a many-ducks scene is trimmed.
inline bool many_ducks_trimmed(int k) {
  return k % 3 == 0;
}

}  // namespace nurbs
