#include "harness/metrics.h"

#include <fmt/format.h>

#include <cfloat>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "reference/trim_classify.h"

namespace nurbs {

double ulps_of_largest_coordinate(double error, double largest_coordinate) {
  // A scene at the origin with all-zero coordinates still has a scale: one float ulp of 1.
  const double scale = FLT_EPSILON * (largest_coordinate > 0 ? largest_coordinate : 1.0);
  return error / scale;
}

namespace {

double normal_angle_deg(const std::array<double, 3>& a, const Point3& b) {
  const double na = std::hypot(a[0], a[1], a[2]), nb = std::hypot(b[0], b[1], b[2]);
  if (!(na > 0) || !(nb > 0)) return 180.0;  // a missing normal is as wrong as it gets
  // atan2 of |a x b| and a.b is accurate for tiny angles, where acos of the dot product is not.
  const double cx = a[1] * b[2] - a[2] * b[1], cy = a[2] * b[0] - a[0] * b[2],
               cz = a[0] * b[1] - a[1] * b[0];
  const double dot = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  return std::atan2(std::hypot(cx, cy, cz), dot) * 180.0 / std::numbers::pi;
}

}  // namespace

std::vector<SurfaceSamples> result_samples(const EvalResult& result) {
  std::vector<SurfaceSamples> samples;
  samples.reserve(result.surfaces.size());
  for (const SurfaceResult& r : result.surfaces) samples.push_back(r.samples);
  return samples;
}

bool same_samples(const std::vector<SurfaceSamples>& a, const std::vector<SurfaceSamples>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].tensor != b[i].tensor || a[i].u != b[i].u || a[i].v != b[i].v) return false;
  return true;
}

void orient_normals(const Scene& scene, EvalResult& result) {
  for (std::size_t i = 0; i < result.surfaces.size() && i < scene.surfaces.size(); ++i) {
    PointArray& normals = result.surfaces[i].normals;
    if (!scene.surfaces[i].reversed || normals.empty()) continue;
    const std::size_t n = 3 * normals.size();
    if (normals.precision() == Precision::f32)
      for (float* c = normals.f32(); c != normals.f32() + n; ++c) *c = -*c;
    else
      for (double* c = normals.f64(); c != normals.f64() + n; ++c) *c = -*c;
  }
}

bool no_inside_samples(const Accuracy& accuracy) {
  return accuracy.trim && accuracy.trim->inside == 0;
}

std::string_view trimming_of(const Capabilities& capabilities, const Scene& scene) {
  if (!scene.has_trims()) return "";
  return capabilities.trims ? "classified" : "untrimmed";
}

namespace {

// Checks the classification inputs of a trimmed surface and adds its boundary and
// misclassification counts to `figures`; `outside_band` counts the samples that were scored.
void count_trim_figures(const Surface& surface, int index, const SurfaceResult& r,
                        const ReferenceSurface& ref, const TrimScoring& scoring,
                        TrimAccuracy& figures, std::size_t& outside_band) {
  const std::size_t n = ref.positions.size();
  if (ref.inside.size() != n || ref.trim_distance.size() != n)
    throw std::runtime_error(
        fmt::format("the reference has no trim classification for trimmed surface '{}' (#{})",
                    surface.name, index));
  if (scoring.strategy_trims && r.inside.empty())
    throw std::runtime_error(
        fmt::format("the strategy trims but returned no inside mask for trimmed surface '{}' (#{})",
                    surface.name, index));
  if (scoring.strategy_trims && r.inside.size() != n)
    throw std::runtime_error(
        fmt::format("inside mask of surface '{}' (#{}) has {} entries for {} samples", surface.name,
                    index, r.inside.size(), n));
  const double band = scoring.band * domain_diagonal(surface);
  for (std::size_t k = 0; k < n; ++k) {
    if (in_trim_band(ref.trim_distance[k], band)) {
      ++figures.boundary;
      continue;
    }
    if (!scoring.strategy_trims) continue;
    ++outside_band;
    if ((r.inside[k] != 0) != (ref.inside[k] != 0)) ++*figures.misclassified;
  }
}

}  // namespace

Accuracy measure_accuracy(const Scene& scene, const EvalResult& result,
                          const std::vector<ReferenceSurface>& reference, const TrimScoring& trim) {
  if (result.surfaces.size() != scene.surfaces.size() || reference.size() != scene.surfaces.size())
    throw std::runtime_error("result has a different number of surfaces than the scene");
  Accuracy acc;
  TrimAccuracy figures;
  figures.band = trim.band;
  if (trim.strategy_trims) figures.misclassified = 0;
  std::size_t outside_band = 0;
  double sum_squares = 0;
  std::size_t count = 0;
  bool with_normals = false;
  double max_angle = 0;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& surface = scene.surfaces[i];
    const SurfaceResult& r = result.surfaces[i];
    const ReferenceSurface& ref = reference[i];
    if (r.positions.size() != ref.positions.size())
      throw std::runtime_error("result has a different number of samples than requested");
    if (surface.trim)
      count_trim_figures(surface, static_cast<int>(i), r, ref, trim, figures, outside_band);
    auto finite = [](const PointArray& points, std::size_t k) {
      const auto p = points[k];
      return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
    };
    for (std::size_t k = 0; k < r.positions.size(); ++k) {
      if (finite(r.positions, k) && (k >= r.normals.size() || finite(r.normals, k))) continue;
      if (acc.non_finite++ == 0)
        acc.first_non_finite = {static_cast<int>(i), r.samples.u_of(k), r.samples.v_of(k)};
    }
    // The part of a trimmed surface outside its face is not the model: its errors do not count.
    auto scored = [&](std::size_t k) { return !surface.trim || ref.inside[k] != 0; };
    for (std::size_t k = 0; k < r.positions.size(); ++k) {
      if (!scored(k)) continue;
      const auto p = r.positions[k];
      const double error = std::hypot(p[0] - ref.positions[k][0], p[1] - ref.positions[k][1],
                                      p[2] - ref.positions[k][2]);
      // !(error <= max) so that NaN (and the first sample) is taken as the worst.
      if (!(error <= acc.max_abs) || count == 0) {
        acc.max_abs = std::isfinite(error) ? error : std::numeric_limits<double>::infinity();
        acc.worst_surface = static_cast<int>(i);
        acc.worst_u = r.samples.u_of(k);
        acc.worst_v = r.samples.v_of(k);
      }
      sum_squares += std::isfinite(error) ? error * error : std::numeric_limits<double>::infinity();
      ++count;
    }
    if (!r.normals.empty() && !ref.normals.empty()) {
      with_normals = true;
      for (std::size_t k = 0; k < r.normals.size(); ++k) {
        if (!scored(k)) continue;
        const double angle = normal_angle_deg(r.normals[k], ref.normals[k]);
        if (!(angle <= max_angle)) max_angle = std::isfinite(angle) ? angle : 180.0;
      }
    }
  }
  acc.rms_abs = count ? std::sqrt(sum_squares / static_cast<double>(count)) : 0;
  const double diagonal = scene.bounding_box_diagonal();
  acc.max_rel = diagonal > 0 ? acc.max_abs / diagonal : acc.max_abs;
  acc.max_ulp = ulps_of_largest_coordinate(acc.max_abs, scene.largest_coordinate());
  if (with_normals) acc.max_normal_angle_deg = max_angle;
  if (scene.has_trims()) {
    figures.inside = count;
    if (figures.misclassified)
      figures.misclassified_rate =
          outside_band ? static_cast<double>(*figures.misclassified) / outside_band : 0.0;
    acc.trim = figures;
  }
  return acc;
}

std::string non_finite_failure(const Accuracy& accuracy, std::size_t samples) {
  if (accuracy.non_finite == 0) return "";
  const NonFiniteSample& first = accuracy.first_non_finite;
  return fmt::format(
      "{} of {} samples are not finite (NaN/Inf position or normal); the first at surface {} "
      "(u, v) = ({:.17g}, {:.17g})",
      accuracy.non_finite, samples, first.surface, first.u, first.v);
}

}  // namespace nurbs
