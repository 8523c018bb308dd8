#include "harness/report/kit.h"

namespace nurbs::report {

ReportSection fig7_time_vs_points(const SectionInput& in) {
  return time_vs_points_of(in, "patch144");
}

}  // namespace nurbs::report
