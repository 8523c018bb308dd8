// The built-in trimmed-plate's face in closed form (scenes/trimmed_plate.h): tests compare a
// classification with it instead of with the classifier that produced it.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "reference/sampling.h"
#include "scenes/trimmed_plate.h"

namespace nurbs::test {

// Signed distance in (u, v) to the face's boundary, negative inside: the rounded rectangle's
// (a rounded box's SDF) against the hole's circle.
inline double trimmed_plate_signed_distance(const TrimmedPlateShape& s, double u, double v) {
  const double centre = (s.low + s.high) / 2, half = (s.high - s.low) / 2 - s.corner_radius;
  const double qu = std::abs(u - centre) - half, qv = std::abs(v - centre) - half;
  const double box = std::hypot(std::max(qu, 0.0), std::max(qv, 0.0)) +
                     std::min(std::max(qu, qv), 0.0) - s.corner_radius;
  const double hole = s.hole_radius - std::hypot(u - s.hole_center_u, v - s.hole_center_v);
  return std::max(box, hole);
}

struct MaskAgainstClosedForm {
  std::size_t inside = 0, checked = 0;
};

// Every sample of a strategy's mask against the closed form (samples within 1e-9 of the boundary
// are skipped: either answer is exact enough there); counts for the callers' own expectations.
inline MaskAgainstClosedForm expect_mask_is_the_closed_form(
    const TrimmedPlateShape& shape, const SurfaceSamples& samples,
    const std::vector<std::uint8_t>& inside) {
  MaskAgainstClosedForm out;
  for (std::size_t k = 0; k < samples.count(); ++k) {
    const double d = trimmed_plate_signed_distance(shape, samples.u_of(k), samples.v_of(k));
    if (std::abs(d) < 1e-9) continue;
    ++out.checked;
    out.inside += inside[k];
    EXPECT_EQ(inside[k], d < 0 ? 1 : 0) << samples.u_of(k) << "," << samples.v_of(k);
  }
  return out;
}

}  // namespace nurbs::test
