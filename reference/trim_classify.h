// Exact point classification against a surface's trimming loops (the reference's notion of
// "inside the trimmed face"), and each sample's distance to the trim boundary in (u, v).
//
// Crossings are counted against the trim curves themselves: every curve is decomposed into
// rational Bézier pieces (The NURBS Book A5.6 in homogeneous 2D), and the roots of
// w(t)·(v(t) − v) on each piece are isolated by Bernstein subdivision and refined by bisection in
// the requested scalar -- never a polyline approximation. A gap between consecutive curves
// (allowed up to Trim::tolerance) is closed by the straight segment between the two ends, so every
// loop is exactly closed for counting. Written once, templated on the scalar: the reference runs it
// in long double, cpu-coxdeboor in double.
#pragma once

#include <cstdint>
#include <vector>

#include "reference/sampling.h"
#include "reference/surface.h"
#include "reference/trim.h"

namespace nurbs {

enum class TrimScalar { f64, long_double };

struct TrimClassification {
  std::vector<std::uint8_t> inside;  // one per sample, in SurfaceSamples order: 1 inside, 0 outside
  // Distance to the nearest trim curve in (u, v); empty unless asked. Within 1e-4 of itself (and
  // 1e-12 of the loops' extent) below 1e-3 of the loops' extent, where boundary bands are
  // chosen, and within 1% beyond: exactness is the classification's job, the distance only
  // decides which samples lie in the band.
  std::vector<double> distance;
};

// Classifies every sample of `samples` against `trim`. Samples of a tensor grid share one
// crossing list per distinct v (O(curves) per row, not per sample). Rows are spread over
// `threads` OpenMP threads (0: OpenMP's default; a single-threaded strategy passes 1).
TrimClassification classify_trim_samples(const Trim& trim, const SurfaceSamples& samples,
                                         bool with_distance, TrimScalar scalar, int threads = 0);

// The (u, v) domain diagonal of a surface: --trim-band is a fraction of it.
double domain_diagonal(const Surface& surface);

}  // namespace nurbs
