#include "scenes/many_ducks.h"

#include <fmt/format.h>

#include <cmath>

#include "scenes/trimmed_plate.h"

namespace nurbs {

Scene many_ducks_scene(const Scene& duck, int n) {
  // Apart, as 000's separate objects are: a step of the duck's whole diagonal each way.
  const double step = 1.1 * duck.bounding_box_diagonal();
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
        p[0] += step * (k % columns);
        p[1] += step * (k / columns);
      }
      if (many_ducks_trimmed(k))
        s.trim = trimmed_plate_trim({}, s.u_min(), s.u_max(), s.v_min(), s.v_max());
      scene.surfaces.push_back(std::move(s));
    }
  return scene;
}

}  // namespace nurbs
