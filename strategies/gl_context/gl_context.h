// The OpenGL plumbing shared by every GL strategy (docs/design.md §GPU plumbing is shared): a
// windowless desktop-GL 3.3 core context on OSMesa or on EGL (the device platform when a real
// GPU is present, else Mesa's surfaceless platform), its function table, the renderer strings for
// the record, and GL errors (GL debug output in debug builds) turned into exceptions.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "strategies/gl_context/gl_functions.h"
#include "strategies/strategy.h"

namespace nurbs::gl {

enum class Platform { osmesa, egl };

std::string_view to_string(Platform platform);
// "osmesa" / "egl"; nullopt for anything else.
std::optional<Platform> parse_platform(std::string_view text);
// The --gl option of a strategy (StrategyOptions.extra["gl"], default egl); throws InputError-like
// std::invalid_argument naming the bad value.
Platform platform_option(const StrategyOptions& options);

// No context on this platform (no EGL display, no OSMesa, GL too old): the strategy is
// unavailable, with this reason.
class UnavailableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A GL error or a debug-output error message, naming where it was detected.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One platform's context and how to make it current and load functions (gl_osmesa.cpp,
// gl_egl.cpp).
class Backend {
 public:
  virtual ~Backend() = default;
  virtual void make_current() = 0;
  virtual void release() = 0;
  virtual void* proc_address(const char* name) = 0;
  virtual std::string description() const = 0;  // "osmesa", "egl-surfaceless", "egl-device"
};

// Draws issued through one Context. A pass is a framebuffer binding drawn into: the draws between
// two bind_framebuffer() calls render into one target, as the papers' passes do (000's ping-pong
// binds a new target for every draw; 002 draws every span quad of a direction into one target).
// Reads of device memory are counted beside them: a host read-back (glReadPixels into host
// memory, glGetBufferSubData) or a device copy (glReadPixels into a pixel-pack buffer, which stays
// on the device: 000 §3.2's output drawn as a vertex buffer without reading it back).
struct DrawCounts {
  std::uint64_t draws = 0;
  std::uint64_t passes = 0;
  std::uint64_t host_read_backs = 0;
  std::uint64_t device_copies = 0;
  DrawCounts operator-(const DrawCounts& earlier) const {
    return {draws - earlier.draws, passes - earlier.passes,
            host_read_backs - earlier.host_read_backs, device_copies - earlier.device_copies};
  }
};

void APIENTRY debug_message(GLenum source, GLenum type, GLuint id, GLenum severity, GLsizei length,
                            const GLchar* message, const void* self);

class Context {
 public:
  // Throws UnavailableError with the reason when the platform cannot give a GL 3.3 core context.
  static std::unique_ptr<Context> create(Platform platform);
  // Whether create(platform) succeeds here; computed once per process and platform.
  static Availability probe(Platform platform);
  // A GL strategy's registry probe: available when either platform is (EGL first; with OSMesa
  // only, --gl osmesa works and the default egl reports at create), else both reasons.
  static Availability probe_any();

  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Makes this context current on the calling thread, releasing another nurbsbench context first
  // (an OSMesa and an EGL context share Mesa's dispatch, so only one may be bound at a time).
  void make_current();
  const Functions& gl() const { return gl_; }

  // The only way to bind a framebuffer (GL_FRAMEBUFFER) or to draw: see DrawCounts.
  void bind_framebuffer(GLuint framebuffer);
  void draw_arrays(GLenum mode, GLint first, GLsizei count);
  // One draw however many instances: what a draw costs the driver is paid once.
  void draw_arrays_instanced(GLenum mode, GLint first, GLsizei count, GLsizei instances);
  void draw_elements(GLenum mode, GLsizei count, GLenum type, const void* indices);
  // glReadPixels of the bound read framebuffer into host memory: a host read-back.
  void read_pixels(GLint x, GLint y, GLsizei width, GLsizei height, GLenum format, GLenum type,
                   void* pixels);
  // glReadPixels into `pack_buffer` (GL_PIXEL_PACK_BUFFER, from byte `offset`): a device copy,
  // no host memory involved. The buffer must hold the pixels; the pack binding is restored to 0.
  void copy_pixels_to_buffer(GLuint pack_buffer, GLint x, GLint y, GLsizei width, GLsizei height,
                             GLenum format, GLenum type, GLintptr offset = 0);
  // glMapBufferRange of [0, bytes) of `buffer` with `access`: mapped for reading it is a host
  // read-back (counted), for writing it is not. Throws Error when the driver maps nothing.
  void* map_buffer(GLuint buffer, GLsizeiptr bytes, GLbitfield access, std::string_view where);
  // glUnmapBuffer; throws Error naming `where` when the content was lost while mapped (GL_FALSE).
  void unmap_buffer(GLuint buffer, std::string_view where);
  // glGetBufferSubData of `buffer` (bound to GL_COPY_READ_BUFFER) into host memory: a host
  // read-back.
  void read_buffer(GLuint buffer, GLintptr offset, GLsizeiptr bytes, void* data);
  // Since the context was created; a strategy records the difference over its evaluate().
  DrawCounts draw_counts() const { return draw_counts_; }

  Platform platform() const { return platform_; }
  const std::string& description() const { return description_; }
  const std::string& renderer() const { return renderer_; }
  const std::string& vendor() const { return vendor_; }
  const std::string& version() const { return version_; }
  const std::string& glsl_version() const { return glsl_version_; }
  // llvmpipe, softpipe, swrast: the "GPU" is the CPU (docs/design.md §Timing).
  bool software() const;
  int max_texture_size() const { return max_texture_size_; }
  int max_viewport() const { return max_viewport_; }
  bool has_extension(std::string_view name) const;
  // The device record every GL strategy starts from: renderer as the name, kind "cpu" on a
  // software rasterizer (with a note saying so), platform/renderer/vendor/version details.
  DeviceInfo device_info() const;

  // glFinish with a bound: a fence sync object waited on with glClientWaitSync for at most
  // device_wait_limit_s() (strategies/device_wait.h), so a device that never finishes throws
  // DeviceTimeout naming `where` instead of hanging. Every GL strategy ends its device work here.
  void finish(std::string_view where);

  // Throws Error if glGetError or (debug builds) debug output reported an error since the last
  // check; `where` names the step ("basis pass 2", "upload").
  void check(std::string_view where);

 private:
  Context(Platform platform, std::unique_ptr<Backend> backend);
  void init();
  friend void debug_message(GLenum, GLenum, GLuint, GLenum, GLsizei, const GLchar*, const void*);
  void count_draw();

  Platform platform_;
  std::unique_ptr<Backend> backend_;
  Functions gl_;
  CountedFunctions counted_;
  DrawCounts draw_counts_;
  bool bound_target_drawn_ = false;  // a draw went into the framebuffer bound last
  std::string description_, renderer_, vendor_, version_, glsl_version_;
  std::vector<std::string> extensions_;
  int max_texture_size_ = 0, max_viewport_ = 0;
  std::vector<std::string> debug_errors_;
};

// GL_TIME_ELAPSED around a strategy's measured device work: the device side of its evaluate
// phase (DeviceTimes::evaluate_s). The query object is made at the first use and reused.
class DeviceTimer {
 public:
  explicit DeviceTimer(Context& context) : context_(context) {}
  ~DeviceTimer();
  DeviceTimer(const DeviceTimer&) = delete;
  DeviceTimer& operator=(const DeviceTimer&) = delete;

  // Makes the context current, runs `work` inside the query, waits for the device
  // (Context::finish) and checks for GL errors, naming `where`; returns the device seconds.
  double time(std::string_view where, const std::function<void()>& work);

 private:
  Context& context_;
  GLuint query_ = 0;
};

// Platform backends; each throws UnavailableError with the reason. Defined only where built.
std::unique_ptr<Backend> create_osmesa_backend(bool debug);
std::unique_ptr<Backend> create_egl_backend(bool debug);

}  // namespace nurbs::gl
