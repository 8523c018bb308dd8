// The C++ builds of the single-source local basis (strategies/gl_tspline/local_basis.h), float as
// accumulate.frag runs it and long double, for the test against the reference.
#pragma once

namespace nurbs::gl_tspline::source {
#define LB_REAL float
#include "strategies/gl_tspline/local_basis.h"
#undef LB_REAL
#define LB_REAL long double
#include "strategies/gl_tspline/local_basis.h"
#undef LB_REAL
}  // namespace nurbs::gl_tspline::source
