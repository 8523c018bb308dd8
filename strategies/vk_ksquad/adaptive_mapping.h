// vk-ksquad's adaptive mapping (003 §4, the tessellator's levels from the local-area-average test
// eq. 3 in the control stage, ksquad.tesc): its host pieces -- the KSQuad corner table and what is
// read back from the capture slots and the levels the control stage stored.
#pragma once

#include <array>
#include <map>
#include <vector>

#include "reference/surface.h"
#include "strategies/strategy.h"
#include "strategies/vk_ksquad/ksquad_layout.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"

namespace nurbs::vk_ksquad {

// The KSQuad corners S(x_k, y_l) of eq. 3, one row (xyz, 1) per (distinct u knot, distinct v knot)
// of each surface, shared by the KSQuads meeting there.
struct Corners {
  std::vector<float> rows;
  std::map<std::array<int, 3>, int> index;  // (surface, first knot index in u, in v) -> row
  std::vector<std::array<int, 5>> spans;    // per row: surface, span_u, span_v, end_u, end_v
  // The row of the corner at (knots_u[a], knots_v[b]).
  int at(const Surface& s, int surface, int a, int b) const;
};
// `on_host`: the rows by the reference in double, rounded to float (vk-corners=host); else
// zeros for ksquad_corners.comp to fill.
Corners corner_table(const Scene& scene, bool on_host);

// The statistics implied by the levels buffer (8 floats per patch: 4 set, 4 wanted); edges past
// `most_level` counted as capped; shared and cracked KSQuad edges (`nonuniform`: by the lattice).
KsquadStatistics adaptive_statistics(KsquadStatistics st, const HostTables& tables,
                                     const std::vector<float>& levels, int most_level,
                                     bool nonuniform);
std::vector<PatchLevels> adaptive_patch_levels(const HostTables& tables,
                                               const std::vector<float>& levels);
// Every captured vertex on each KSQuad's four edges (`region` slots per patch).
std::vector<CapturedEdge> adaptive_edges(const HostTables& tables, const std::vector<float>& slots,
                                         std::size_t region, int max_level);
// Captured vertices gathered per surface (adaptive and nonuniform read-backs): add() a slot's (u,
// v, x, y, z) and, when normals were asked for, its normal; result() the EvalResult.
class CapturedSamples {
 public:
  CapturedSamples(std::size_t surface_count, bool normals);
  void add(int surface, const float* uvxyz, const float* normal);
  EvalResult result();

 private:
  EvalResult out_;
  bool normals_;
  std::vector<std::vector<float>> xyz_, normal_;
};

// The samples the tessellator chose, per surface, with normals where `slot_normals` is given.
EvalResult adaptive_result(const HostTables& tables, const std::vector<float>& slots,
                           const std::vector<float>& slot_normals, std::size_t region,
                           std::size_t surface_count);

}  // namespace nurbs::vk_ksquad
