#include "harness/report/kit.h"

namespace nurbs::report {

// 001 could not time T-splines ("due to limitations of the hardware we were not able to implement
// T-spline evaluation on the GPU"); this is the Fig 9 they would have drawn, on a T-mesh with
// T-junctions, every strategy that evaluates T-splines.
ReportSection fig9_tspline_time_vs_points(const SectionInput& in) {
  return time_vs_points_of(in, "tspline-tjunction");
}

}  // namespace nurbs::report
