#include "reference/trim_classify.h"

#include <cmath>
#include <stdexcept>

namespace nurbs {

TrimClassification classify_trim_samples(const Trim&, const SurfaceSamples&, bool, TrimScalar) {
  throw std::logic_error("classify_trim_samples: being written (contract commit)");
}

double domain_diagonal(const Surface& s) {
  return std::hypot(s.u_max() - s.u_min(), s.v_max() - s.v_min());
}

}  // namespace nurbs
