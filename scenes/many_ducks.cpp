#include "scenes/many_ducks.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "scenes/trimmed_plate.h"

namespace nurbs {

Scene many_ducks_scene(const Scene& duck, int n) {
  Point3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Surface& s : duck.surfaces)
    for (const Point3& p : s.points)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], p[c]);
        hi[c] = std::max(hi[c], p[c]);
      }
  // A tenth of the duck's size between neighbours: apart, as 000's separate objects are.
  const double step_x = 1.1 * (hi[0] - lo[0]), step_y = 1.1 * (hi[1] - lo[1]);
  const int columns = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  Scene scene{fmt::format("many-ducks-{}", n),
              fmt::format("{} ducks ({} surfaces) on a grid, ducks 0, 3, 6, ... ({} of them) "
                          "trimmed to a rounded rectangle with a hole in each surface's domain",
                          n, 3 * n, (n + 2) / 3),
              {}};
  for (int k = 0; k < n; ++k)
    for (const Surface& original : duck.surfaces) {
      Surface s = original;
      s.name = fmt::format("duck{}.{}", k, original.name);
      for (Point3& p : s.points) {
        p[0] += step_x * (k % columns);
        p[1] += step_y * (k / columns);
      }
      if (many_ducks_trimmed(k))
        s.trim = trimmed_plate_trim({}, s.u_min(), s.u_max(), s.v_min(), s.v_max());
      scene.surfaces.push_back(std::move(s));
    }
  return scene;
}

}  // namespace nurbs
