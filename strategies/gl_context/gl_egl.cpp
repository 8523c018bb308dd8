// EGL backend, no window system: the device platform (EGL_EXT_platform_device) on the first
// hardware device, else Mesa's surfaceless platform (EGL_MESA_platform_surfaceless, llvmpipe
// here). A desktop GL 3.3 core context is bound with no surface (EGL_KHR_surfaceless_context).
#define EGL_NO_X11
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <fmt/format.h>

#include <cstring>
#include <map>
#include <mutex>
#include <vector>

#include "strategies/gl_context/gl_context.h"

namespace nurbs::gl {
namespace {

bool has_word(const char* list, std::string_view word) {
  if (!list) return false;
  std::string_view s(list);
  for (std::size_t pos = 0; pos < s.size();) {
    const std::size_t end = std::min(s.find(' ', pos), s.size());
    if (s.substr(pos, end - pos) == word) return true;
    pos = end + 1;
  }
  return false;
}

std::string egl_error_name(EGLint e) {
  switch (e) {
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    default:
      return fmt::format("EGL error 0x{:04x}", e);
  }
}

// eglInitialize is reference-counted here so that one context's eglTerminate does not pull the
// display from under another (EGL displays are per-process singletons per platform/device).
std::mutex display_mutex;
std::map<EGLDisplay, int> display_users;

bool initialize(EGLDisplay display) {
  if (display == EGL_NO_DISPLAY) return false;
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) return false;
  std::lock_guard lock(display_mutex);
  ++display_users[display];
  return true;
}

void release_display(EGLDisplay display) {
  std::lock_guard lock(display_mutex);
  if (--display_users[display] == 0) {
    eglTerminate(display);
    display_users.erase(display);
  }
}

struct Display {
  EGLDisplay display = EGL_NO_DISPLAY;
  std::string description;
};

class EglBackend final : public Backend {
 public:
  EglBackend(Display display, bool debug)
      : display_(display.display), description_(display.description) {
    if (!eglBindAPI(EGL_OPENGL_API))
      throw UnavailableError(fmt::format("EGL ({}): desktop OpenGL API not supported: {}",
                                         description_, egl_error_name(eglGetError())));
    const char* extensions = eglQueryString(display_, EGL_EXTENSIONS);
    if (!has_word(extensions, "EGL_KHR_surfaceless_context"))
      throw UnavailableError(
          fmt::format("EGL ({}): EGL_KHR_surfaceless_context not supported", description_));
    EGLConfig config = nullptr;
    if (!has_word(extensions, "EGL_KHR_no_config_context")) {
      const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
      EGLint n = 0;
      if (!eglChooseConfig(display_, config_attributes, &config, 1, &n) || n < 1)
        throw UnavailableError(
            fmt::format("EGL ({}): no config with EGL_OPENGL_BIT", description_));
    }
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                         3,
                                         EGL_CONTEXT_MINOR_VERSION,
                                         3,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                         EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                         EGL_CONTEXT_OPENGL_DEBUG,
                                         debug ? EGL_TRUE : EGL_FALSE,
                                         EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attributes);
    if (context_ == EGL_NO_CONTEXT)
      throw UnavailableError(fmt::format("EGL ({}): no OpenGL 3.3 core context: {}", description_,
                                         egl_error_name(eglGetError())));
  }
  ~EglBackend() override {
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    release_display(display_);
  }
  void make_current() override {
    eglBindAPI(EGL_OPENGL_API);
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      throw UnavailableError(fmt::format("EGL ({}): eglMakeCurrent failed: {}", description_,
                                         egl_error_name(eglGetError())));
  }
  void release() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  }
  // Core GL functions too: Mesa has EGL_KHR_get_all_proc_addresses.
  void* proc_address(const char* name) override {
    return reinterpret_cast<void*>(eglGetProcAddress(name));
  }
  std::string description() const override { return description_; }

 private:
  EGLDisplay display_;
  std::string description_;
  EGLContext context_ = EGL_NO_CONTEXT;
};

// The first hardware EGL device (Mesa marks its software device EGL_MESA_device_software), or
// EGL_NO_DISPLAY.
Display device_display(const char* client_extensions, std::vector<std::string>& tried) {
  if (!has_word(client_extensions, "EGL_EXT_device_enumeration") ||
      !has_word(client_extensions, "EGL_EXT_platform_device"))
    return {};
  auto query_devices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto query_device_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  auto platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!query_devices || !query_device_string || !platform_display) return {};
  EGLDeviceEXT devices[16];
  EGLint count = 0;
  if (!query_devices(16, devices, &count)) return {};
  for (EGLint i = 0; i < count; ++i) {
    const char* device_extensions = query_device_string(devices[i], EGL_EXTENSIONS);
    if (has_word(device_extensions, "EGL_MESA_device_software")) continue;
    EGLDisplay display = platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
    if (initialize(display)) return {display, fmt::format("egl-device {}", i)};
    tried.push_back(fmt::format("device {}: eglInitialize failed", i));
  }
  return {};
}

Display surfaceless_display(const char* client_extensions, std::vector<std::string>& tried) {
  if (!has_word(client_extensions, "EGL_MESA_platform_surfaceless")) {
    tried.push_back("EGL_MESA_platform_surfaceless not supported");
    return {};
  }
  auto platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!platform_display) return {};
  EGLDisplay display =
      platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (initialize(display)) return {display, "egl-surfaceless"};
  tried.push_back(
      fmt::format("surfaceless: eglInitialize failed: {}", egl_error_name(eglGetError())));
  return {};
}

}  // namespace

std::unique_ptr<Backend> create_egl_backend(bool debug) {
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!client_extensions)
    throw UnavailableError(fmt::format("EGL: no client extensions (no EGL implementation?): {}",
                                       egl_error_name(eglGetError())));
  std::vector<std::string> tried;
  for (auto find : {&device_display, &surfaceless_display}) {
    Display display = find(client_extensions, tried);
    if (display.display == EGL_NO_DISPLAY) continue;
    try {
      return std::make_unique<EglBackend>(display, debug);
    } catch (const UnavailableError& e) {
      release_display(display.display);
      tried.push_back(e.what());
    }
  }
  throw UnavailableError(fmt::format("EGL: no display: {}",
                                     tried.empty() ? "no device or surfaceless platform"
                                                   : fmt::format("{}", fmt::join(tried, "; "))));
}

}  // namespace nurbs::gl
