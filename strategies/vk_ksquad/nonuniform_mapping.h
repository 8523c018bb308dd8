// vk-ksquad's nonuniform mapping (003 §4's third: the control stage's lower level from eq. 3, then
// a geometry stage applying eq. 4 and eq. 5 and the Exact Visible Set culling to each KSDie;
// ksquad.tesc, ksquad_nonuniform.tese, ksquad_nonuniform.geom): its host pieces -- the friend
// surfaces found once on the CPU, and what is read back from the geometry stage's records.
#pragma once

#include <cstddef>
#include <vector>

#include "reference/surface.h"
#include "strategies/strategy.h"
#include "strategies/vk_ksquad/ksquad_layout.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"

namespace nurbs::vk_ksquad {

// 003 §3.1's friend surfaces, our test for them: side e of a surface's domain (0 u = lo, 1 v = lo,
// 2 u = hi, 3 v = hi) is shared with side e' of another surface when the two boundary curves agree
// (either direction) at kFriendSamples points within kFriendDistance x the scene's control-point
// bounding-box diagonal; the two are friends (G1 across it) when at each of those points where
// both normals are defined they are parallel, either orientation, within kFriendAngleDeg. Per
// surface, the mask of its sides shared with a surface that is not its friend (the sides eq. 5
// oversamples); a side shared with only part of another's (a T-junction layout) is not seen.
inline constexpr int kFriendSamples = 9;
inline constexpr double kFriendDistance = 1e-6;
inline constexpr double kFriendAngleDeg = 0.5;
std::vector<int> friendless_sides(const Scene& scene);

// The number of KSDie slots per patch (max_level^2).
inline std::size_t ksdie_slots(int max_level) {
  return static_cast<std::size_t>(max_level) * static_cast<std::size_t>(max_level);
}

// The records of the KSDice each patch's lattice (the levels buffer's set levels) started.
std::vector<KsdieRecord> nonuniform_records(const HostTables& tables,
                                            const std::vector<float>& levels,
                                            const std::vector<int>& ksdice, int max_level);
// The nonuniform counters of `st` from the records.
KsquadStatistics nonuniform_statistics(KsquadStatistics st,
                                       const std::vector<KsdieRecord>& records);
// Every vertex the geometry stage emitted, per surface: (u, v), positions and, with `normals`,
// normals (an emitted vertex shared by neighbouring KSDice is returned by each).
EvalResult nonuniform_result(const HostTables& tables, const std::vector<float>& slots,
                             bool normals, int max_level, std::size_t surface_count);

}  // namespace nurbs::vk_ksquad
