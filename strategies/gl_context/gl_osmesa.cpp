// OSMesa backend: Mesa's off-screen GL, no display of any kind. A desktop GL 3.3 core profile is
// requested through OSMesaCreateContextAttribs (the legacy OSMesaCreateContext gives a 2.1/3.x
// compatibility context without GLSL 3.30 core on some Mesa versions).
#include "strategies/gl_context/gl_context.h"

// osmesa.h includes GL/gl.h, whose GL 1.x prototypes and types clash with GL/glcorearb.h (already
// included, through gl_functions.h): skip it and give osmesa.h the two macros it wants from it.
#define __gl_h_
#ifndef GLAPIENTRY
#define GLAPIENTRY APIENTRY
#endif
#include <GL/osmesa.h>
#include <fmt/format.h>

#include <array>

namespace nurbs::gl {
namespace {

class OsmesaBackend final : public Backend {
 public:
  OsmesaBackend() {
    const int attributes[] = {OSMESA_FORMAT,
                              OSMESA_RGBA,
                              OSMESA_DEPTH_BITS,
                              0,
                              OSMESA_STENCIL_BITS,
                              0,
                              OSMESA_ACCUM_BITS,
                              0,
                              OSMESA_PROFILE,
                              OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION,
                              3,
                              OSMESA_CONTEXT_MINOR_VERSION,
                              3,
                              0};
    context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!context_)
      throw UnavailableError("OSMesa: OSMesaCreateContextAttribs failed (no GL 3.3 core profile)");
  }
  ~OsmesaBackend() override { OSMesaDestroyContext(context_); }

  // OSMesa needs a colour buffer to bind; every pass renders into FBOs, so 1x1 is enough.
  void make_current() override {
    if (!OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 1, 1))
      throw UnavailableError("OSMesa: OSMesaMakeCurrent failed");
  }
  void release() override { OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0); }
  void* proc_address(const char* name) override {
    return reinterpret_cast<void*>(OSMesaGetProcAddress(name));
  }
  std::string description() const override { return "osmesa"; }

 private:
  OSMesaContext context_ = nullptr;
  std::array<unsigned char, 4> buffer_{};
};

}  // namespace

std::unique_ptr<Backend> create_osmesa_backend(bool /*debug: OSMesa has no debug-context flag;
                                                     KHR_debug output works without one*/) {
  return std::make_unique<OsmesaBackend>();
}

}  // namespace nurbs::gl
