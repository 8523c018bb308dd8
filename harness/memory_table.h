// RPNS Table 1 (003 §2): what a scene costs to hold as NURBS and after the decomposition into
// rational Bézier patches, and its number of KSQuads. Counting only -- reference/
// bezier_decomposition.h's ksquad_count is the one place patches/KSQuads are counted.
//
// Bytes are those of the control points as a device holds them, homogeneous float32
// (w*x, w*y, w*z, w) = 16 bytes each. Knots are left out of both columns: the paper's NURBS#M and
// Bezier#M do not say whether they count them (a Bézier patch needs only its parameter interval,
// NURBS their knots; both are small next to the points). The paper's "control points of all the
// Bézier surfaces" reads two ways, so both are counted: per patch, (p+1)(q+1) each, boundary
// points repeated as a patch list holds them (bezier_control_points); and with the boundary row
// that adjacent patches of one surface share held once, (su*p+1)(sv*q+1) for su x sv non-empty
// spans (bezier_shared_control_points; separate surfaces share nothing, even where they touch).
#pragma once

#include <cstddef>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "reference/surface.h"

namespace nurbs {

inline constexpr std::size_t kBytesPerControlPoint = 16;

struct MemoryRow {
  std::string scene;
  std::size_t surfaces = 0;
  std::size_t ksquads = 0;  // = Bézier patches: non-empty (u-span, v-span) pairs
  std::size_t nurbs_control_points = 0;
  std::size_t bezier_control_points = 0;
  std::size_t bezier_shared_control_points = 0;
  std::size_t nurbs_bytes() const { return nurbs_control_points * kBytesPerControlPoint; }
  std::size_t bezier_bytes() const { return bezier_control_points * kBytesPerControlPoint; }
  std::size_t bezier_shared_bytes() const {
    return bezier_shared_control_points * kBytesPerControlPoint;
  }
  double ratio() const { return ratio_to_nurbs(bezier_control_points); }
  double shared_ratio() const { return ratio_to_nurbs(bezier_shared_control_points); }

 private:
  double ratio_to_nurbs(std::size_t points) const {
    return nurbs_control_points
               ? static_cast<double>(points) / static_cast<double>(nurbs_control_points)
               : 0.0;
  }
};

MemoryRow memory_row(const Scene& scene);

std::string memory_table_text(const std::vector<MemoryRow>& rows);
nlohmann::json memory_table_json(const std::vector<MemoryRow>& rows);

}  // namespace nurbs
