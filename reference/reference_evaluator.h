// The reference: every sample of a request evaluated in extended precision (long double by
// default, __float128 on request) with the Piegl & Tiller algorithms of nurbs_math.h, then
// rounded to double. Everything a strategy returns is compared with this, at the strategy's own
// requested (u, v).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "reference/sampling.h"
#include "reference/scalar.h"
#include "reference/surface.h"

namespace nurbs {

enum class ReferencePrecision { long_double, float128 };

bool parse_reference_precision(std::string_view text, ReferencePrecision& out);
std::string_view to_string(ReferencePrecision p);

struct ReferenceSurface {
  std::vector<Point3> positions;  // one per sample, in SurfaceSamples order
  std::vector<Point3> normals;  // unit normals (empty unless requested); flipped on a reversed face
  // Trimmed surfaces only (empty otherwise): the exact classification of every sample
  // (reference/trim_classify.h, in long double) and its distance to the trim boundary in (u, v).
  std::vector<std::uint8_t> inside;
  std::vector<double> trim_distance;
};

// Runs `work.template operator()<T>()` with T the extended-precision scalar `precision` names:
// long double, or __float128 where the build has it (std::invalid_argument where it does not).
template <typename Work>
decltype(auto) with_reference_scalar(ReferencePrecision precision, Work&& work) {
#if NURBSBENCH_HAS_FLOAT128
  if (precision == ReferencePrecision::float128) return work.template operator()<float128>();
#else
  if (precision == ReferencePrecision::float128)
    throw std::invalid_argument("this build has no __float128 (compiler or platform)");
#endif
  return work.template operator()<long double>();
}

std::vector<ReferenceSurface> evaluate_reference(
    const Scene& scene, const std::vector<SurfaceSamples>& samples, bool with_normals,
    ReferencePrecision precision = ReferencePrecision::long_double);

}  // namespace nurbs
