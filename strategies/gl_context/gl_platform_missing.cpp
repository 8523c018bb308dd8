// The platform backend that was not built (its development package was missing at configure).
#include "strategies/gl_context/gl_context.h"

namespace nurbs::gl {

#ifdef NURBSBENCH_NO_OSMESA
std::unique_ptr<Backend> create_osmesa_backend(bool) {
  throw UnavailableError("OSMesa: not built with OSMesa (libosmesa6-dev missing)");
}
#endif
#ifdef NURBSBENCH_NO_EGL
std::unique_ptr<Backend> create_egl_backend(bool) {
  throw UnavailableError("EGL: not built with EGL (libegl-dev missing)");
}
#endif

}  // namespace nurbs::gl
