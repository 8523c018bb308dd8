// Shared by the direct-trimming tests (C++ path, cl-stair, vk-ksquad): a strategy's mask against
// the reference classifier (long double, with distances) outside the boundary band, and the cost
// bound the classifier's reads cannot exceed.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "reference/trim_classify.h"
#include "strategies/trim_direct/trim_tables.h"

namespace nurbs::test {

// The harness's default --trim-band (harness/metrics.h kDefaultTrimBand).
inline constexpr double kTrimBand = 1e-7;

struct TrimMismatch {
  std::size_t compared = 0, misclassified = 0, in_band = 0, inside = 0;
  TrimMismatch& operator+=(const TrimMismatch& o) {
    compared += o.compared;
    misclassified += o.misclassified;
    in_band += o.in_band;
    inside += o.inside;
    return *this;
  }
};

inline TrimMismatch compare_with_reference(const Surface& surface, const SurfaceSamples& samples,
                                           const std::vector<std::uint8_t>& inside,
                                           double band = kTrimBand) {
  TrimMismatch m;
  const TrimClassification ref =
      classify_trim_samples(*surface.trim, samples, true, TrimScalar::long_double);
  const double limit = band * domain_diagonal(surface);
  for (std::size_t k = 0; k < samples.count(); ++k) {
    if (ref.distance[k] < limit) {
      ++m.in_band;
      continue;
    }
    ++m.compared;
    m.inside += ref.inside[k];
    m.misclassified += k >= inside.size() || inside[k] != ref.inside[k];
  }
  return m;
}

// The most elements td_classify can read for one sample of these tables.
template <typename T>
int max_reads_bound(const trim_direct::TrimTables<T>& t) {
  int bound = 0;
  for (const auto& s : t.surfaces) {
    if (s.base < 0) continue;
    const int rows = t.ints[s.base];
    int widest = 0;
    for (int r = 0; r < rows; ++r) {
      int cost = 0;
      for (int e = t.ints[s.base + 2 + r]; e < t.ints[s.base + 3 + r]; e += 2)
        cost += 4 + 3 * (t.ints[e + 1] + 1);
      widest = std::max(widest, cost);
    }
    const int search = static_cast<int>(std::ceil(std::log2(std::max(rows, 1)))) + 1;
    bound = std::max(bound, 4 + search + 2 + widest);
  }
  return bound;
}

}  // namespace nurbs::test
