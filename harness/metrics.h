// Accuracy of one strategy's result against the reference at the same (u, v) (DESIGN.md,
// "Reference and accuracy"). NaN-safe: a non-finite coordinate counts as an infinite error.
#pragma once

#include <optional>
#include <vector>

#include "reference/reference_evaluator.h"
#include "strategies/strategy.h"

namespace nurbs {

struct Accuracy {
  double max_abs = 0;  // model units
  double rms_abs = 0;
  double max_rel = 0;  // max_abs / diagonal of the control points' bounding box
  double max_ulp = 0;  // max_abs / (FLT_EPSILON * largest |coordinate|)
  // where max_abs occurred
  int worst_surface = 0;
  double worst_u = 0, worst_v = 0;
  std::size_t non_finite = 0;  // samples with a NaN/Inf coordinate
  std::optional<double> max_normal_angle_deg;
};

Accuracy measure_accuracy(const Scene& scene, const EvalResult& result,
                          const std::vector<ReferenceSurface>& reference);

// The (u, v) each result surface was evaluated at; equal to sample_parameters(request) except for
// strategies that choose their own samples (Capabilities::chooses_own_samples).
std::vector<SurfaceSamples> result_samples(const EvalResult& result);
// Same layout and the same parameters, bit for bit.
bool same_samples(const std::vector<SurfaceSamples>& a, const std::vector<SurfaceSamples>& b);

// Same as above for a single scalar error scale; exposed for the tests of the formula.
double ulps_of_largest_coordinate(double error, double largest_coordinate);

}  // namespace nurbs
