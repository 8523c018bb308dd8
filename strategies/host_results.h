// How a device strategy hands its results to the harness: into the EvalResult of the previous
// repetition (Strategy::read_back_into), keeping its storage, so that a timed read-back pays for
// its bytes and not for allocations and the page faults of fresh vectors. Before this, each GPU
// strategy allocated an intermediate vector of the whole result and then a PointArray per surface
// on every call: two allocations and two copies of every byte, which held read-back to 0.5-1 GB/s
// on the software drivers where the host strategies deliver the same bytes at 8-14 GB/s.
#pragma once

#include <cstddef>
#include <cstring>
#include <type_traits>
#include <vector>

#include "reference/point_array.h"
#include "reference/sampling.h"
#include "strategies/strategy.h"

namespace nurbs {

// Makes `out` hold one SurfaceResult per entry of `samples`, each with positions (and normals
// when `normals`) sized for its samples at `precision`, reusing the storage `out` already has.
// Trim masks are cleared; values of kept storage are left for the caller to overwrite.
inline void shape_results(EvalResult& out, const std::vector<SurfaceSamples>& samples,
                          Precision precision, bool normals) {
  out.surfaces.resize(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    SurfaceResult& r = out.surfaces[i];
    r.samples = samples[i];
    r.positions.reset(precision, samples[i].count());
    if (normals)
      r.normals.reset(precision, samples[i].count());
    else
      r.normals = PointArray();
    r.inside.clear();
  }
}

// Each surface's `field` (&SurfaceResult::positions or ::normals, already shaped by shape_results)
// from `from`: every surface's points back to back in `out`'s order, x y z per point, as the
// device strategies write them. One copy of each byte, straight from where the device left it (a
// mapping or a staging buffer).
template <typename T>
void scatter_into(EvalResult& out, PointArray SurfaceResult::*field, const T* from) {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>);
  std::size_t base = 0;
  for (SurfaceResult& r : out.surfaces) {
    PointArray& to = r.*field;
    const std::size_t n = to.size();
    if (n > 0) std::memcpy(to.data<T>(), from + 3 * base, 3 * n * sizeof(T));
    base += n;
  }
}

// `out` shaped for `samples` and filled from positions (and normals, or nullptr for none) laid out
// as scatter_into reads them.
template <typename T>
void scatter_points(EvalResult& out, const std::vector<SurfaceSamples>& samples, const T* positions,
                    const T* normals) {
  shape_results(out, samples, std::is_same_v<T, float> ? Precision::f32 : Precision::f64,
                normals != nullptr);
  scatter_into(out, &SurfaceResult::positions, positions);
  if (normals) scatter_into(out, &SurfaceResult::normals, normals);
}

}  // namespace nurbs
