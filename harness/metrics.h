// Accuracy of one strategy's result against the reference at the same (u, v) (docs/design.md
// §Reference and accuracy). NaN-safe: a non-finite coordinate counts as an infinite error.
// On a trimmed surface only the samples the reference classifies inside the face are scored: the
// rest of the surface is not part of the model (the real-CAD issue).
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "reference/reference_evaluator.h"
#include "strategies/strategy.h"

namespace nurbs {

// --trim-band's default: samples closer to the trim boundary than this fraction of the surface's
// (u, v) domain diagonal are "boundary" samples, whose classification is not scored (a strategy
// classifying in float32 cannot resolve them, and the exact answer there is a matter of rounding
// the parameter).
inline constexpr double kDefaultTrimBand = 1e-7;

// A sample nearer to the trim boundary than `band_units` ((u, v) units: band x the surface's
// domain_diagonal) is in the boundary band, where its classification is not scored; NaN-safe (a
// distance that is not a number is in the band).
inline bool in_trim_band(double distance, double band_units) {
  return !(distance >= band_units);
}

struct TrimScoring {
  double band = kDefaultTrimBand;  // fraction of each trimmed surface's domain_diagonal
  // Capabilities::trims: the strategy's classification is scored, and a trimmed surface without
  // an inside mask is a failed measurement.
  bool strategy_trims = false;
};

// The trim figures of a scene with at least one trimmed surface.
struct TrimAccuracy {
  double band = kDefaultTrimBand;  // as given, a fraction of the domain diagonal
  // Samples the position and normal errors are over: inside their face by the reference's exact
  // classification (every sample of an untrimmed surface). 0 = the errors are over nothing.
  std::size_t inside = 0;
  // Samples of trimmed surfaces nearer to the boundary than band x domain_diagonal: their
  // classification is not scored.
  std::size_t boundary = 0;
  // Strategies that trim only: samples outside the band classified differently from the
  // reference, and that count over the samples outside the band (0 when there are none).
  std::optional<std::size_t> misclassified;
  std::optional<double> misclassified_rate;
};

struct NonFiniteSample {
  int surface = 0;
  double u = 0, v = 0;
};

struct Accuracy {
  double max_abs = 0;  // model units
  double rms_abs = 0;
  double max_rel = 0;  // max_abs / diagonal of the control points' bounding box
  double max_ulp = 0;  // max_abs / (FLT_EPSILON * largest |coordinate|)
  // where max_abs occurred
  int worst_surface = 0;
  double worst_u = 0, worst_v = 0;
  // Samples with a NaN/Inf position or normal coordinate, wherever they lie (outside the face and
  // in the trim band too): a strategy that returns them has failed, whatever its errors inside.
  std::size_t non_finite = 0;
  NonFiniteSample first_non_finite;  // meaningful when non_finite > 0
  std::optional<double> max_normal_angle_deg;
  std::optional<TrimAccuracy> trim;  // present exactly when the scene has trims
};

// A trimmed scene none of whose samples lies inside a face: the errors are over nothing (0), which
// every table and gate says instead of showing a perfect score.
bool no_inside_samples(const Accuracy& accuracy);

// `result`'s normals are the face's (orient_normals applied). Throws std::runtime_error when the
// result does not match the scene (surface or sample counts, an inside mask of the wrong size, or
// a strategy that trims without a mask for a trimmed surface): a failed measurement.
Accuracy measure_accuracy(const Scene& scene, const EvalResult& result,
                          const std::vector<ReferenceSurface>& reference,
                          const TrimScoring& trim = {});

// "N of M samples are not finite (...); the first at surface S (u, v)" when accuracy has any
// non-finite sample, else "": why such a record is failed, never ok.
std::string non_finite_failure(const Accuracy& accuracy, std::size_t samples);

// Strategies compute S_u x S_v; a reversed face's outward normal is its negation
// (Surface::reversed). Flips the normals of those surfaces in place, for scoring and for output.
void orient_normals(const Scene& scene, EvalResult& result);

// What a record says about trimming: "" (the scene has no trims), "classified" (the strategy
// trims) or "untrimmed" (it evaluated the whole surfaces; its errors are still over the inside).
std::string_view trimming_of(const Capabilities& capabilities, const Scene& scene);

// The (u, v) each result surface was evaluated at; equal to sample_parameters(request) except for
// strategies that choose their own samples (Capabilities::chooses_own_samples).
std::vector<SurfaceSamples> result_samples(const EvalResult& result);
// Same layout and the same parameters, bit for bit.
bool same_samples(const std::vector<SurfaceSamples>& a, const std::vector<SurfaceSamples>& b);

// Same as above for a single scalar error scale; exposed for the tests of the formula.
double ulps_of_largest_coordinate(double error, double largest_coordinate);

}  // namespace nurbs
