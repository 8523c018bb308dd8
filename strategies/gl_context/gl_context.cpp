#include "strategies/gl_context/gl_context.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <mutex>
#include <type_traits>

#include "strategies/device_wait.h"

namespace nurbs::gl {
namespace {

#ifdef NDEBUG
constexpr bool kDebugOutput = false;
#else
constexpr bool kDebugOutput =
    true;  // the issue: GL debug output turned into errors in debug builds
#endif

// The context bound on this thread by nurbsbench (see Context::make_current).
thread_local Context* current_context = nullptr;
thread_local Backend* current_backend = nullptr;

std::string gl_string(const Functions& gl, GLenum name) {
  const GLubyte* s = gl.GetString(name);
  return s ? reinterpret_cast<const char*>(s) : "";
}

std::string_view error_name(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    default:
      return "GL error";
  }
}

}  // namespace

std::string_view to_string(Platform platform) {
  return platform == Platform::osmesa ? "osmesa" : "egl";
}

std::optional<Platform> parse_platform(std::string_view text) {
  if (text == "osmesa") return Platform::osmesa;
  if (text == "egl") return Platform::egl;
  return std::nullopt;
}

Platform platform_option(const StrategyOptions& options) {
  const auto it = options.extra.find("gl");
  if (it == options.extra.end() || it->second.empty()) return Platform::egl;
  if (auto p = parse_platform(it->second)) return *p;
  throw std::invalid_argument(fmt::format("--gl = '{}': must be osmesa or egl", it->second));
}

std::unique_ptr<Context> Context::create(Platform platform) {
  std::unique_ptr<Backend> backend = platform == Platform::osmesa
                                         ? create_osmesa_backend(kDebugOutput)
                                         : create_egl_backend(kDebugOutput);
  std::unique_ptr<Context> context(new Context(platform, std::move(backend)));
  context->init();  // a throw here still runs ~Context, which unbinds the backend
  return context;
}

Availability Context::probe(Platform platform) {
  static std::mutex mutex;
  static std::map<Platform, Availability> cache;
  std::lock_guard lock(mutex);
  if (auto it = cache.find(platform); it != cache.end()) return it->second;
  Availability a;
  try {
    create(platform);
    a.available = true;
  } catch (const std::exception& e) {
    a.reason = e.what();
  }
  return cache[platform] = a;
}

Availability Context::probe_any() {
  const Availability egl = probe(Platform::egl);
  if (egl.available) return egl;
  const Availability osmesa = probe(Platform::osmesa);
  if (osmesa.available) return osmesa;
  return {false, fmt::format("{}; {}", egl.reason, osmesa.reason)};
}

Context::Context(Platform platform, std::unique_ptr<Backend> backend)
    : platform_(platform), backend_(std::move(backend)) {}

void Context::init() {
  description_ = backend_->description();
  make_current();
  std::vector<std::string> missing;
  auto load = [&](auto& entry, const char* name) {
    entry =
        reinterpret_cast<std::remove_reference_t<decltype(entry)>>(backend_->proc_address(name));
    if (!entry) missing.push_back(name);
  };
#define NURBSBENCH_GL_LOAD(type, name) load(gl_.name, "gl" #name);
  NURBSBENCH_GL_FUNCTIONS(NURBSBENCH_GL_LOAD)
#undef NURBSBENCH_GL_LOAD
#define NURBSBENCH_GL_LOAD(type, name) load(counted_.name, "gl" #name);
  NURBSBENCH_GL_COUNTED_FUNCTIONS(NURBSBENCH_GL_LOAD)
#undef NURBSBENCH_GL_LOAD
  if (!missing.empty())
    throw UnavailableError(
        fmt::format("{}: GL entry points not found: {}", description_, fmt::join(missing, ", ")));
  renderer_ = gl_string(gl_, GL_RENDERER);
  vendor_ = gl_string(gl_, GL_VENDOR);
  version_ = gl_string(gl_, GL_VERSION);
  glsl_version_ = gl_string(gl_, GL_SHADING_LANGUAGE_VERSION);
  GLint count = 0;
  gl_.GetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i)
    extensions_.emplace_back(
        reinterpret_cast<const char*>(gl_.GetStringi(GL_EXTENSIONS, static_cast<GLuint>(i))));
  gl_.GetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture_size_);
  GLint viewport[2] = {0, 0};
  gl_.GetIntegerv(GL_MAX_VIEWPORT_DIMS, viewport);
  max_viewport_ = std::min(viewport[0], viewport[1]);
  // GL_TIME_ELAPSED queries and float render targets are core in 3.3, asked for at creation.
  if (kDebugOutput) {
    gl_.Enable(GL_DEBUG_OUTPUT);
    gl_.Enable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    gl_.DebugMessageCallback(&debug_message, static_cast<const void*>(this));
    gl_.DebugMessageControl(GL_DONT_CARE, GL_DONT_CARE, GL_DONT_CARE, 0, nullptr, GL_TRUE);
  }
  check("context creation");
}

Context::~Context() {
  if (current_context == this) {
    backend_->release();
    current_context = nullptr;
    current_backend = nullptr;
  }
}

void Context::make_current() {
  if (current_backend == backend_.get()) return;
  if (current_backend) current_backend->release();
  current_backend = nullptr;
  current_context = nullptr;
  backend_->make_current();
  current_backend = backend_.get();
  current_context = this;
}

void Context::bind_framebuffer(GLuint framebuffer) {
  counted_.BindFramebuffer(GL_FRAMEBUFFER, framebuffer);
  bound_target_drawn_ = false;
}

void Context::draw_arrays(GLenum mode, GLint first, GLsizei count) {
  counted_.DrawArrays(mode, first, count);
  count_draw();
}

void Context::draw_arrays_instanced(GLenum mode, GLint first, GLsizei count, GLsizei instances) {
  counted_.DrawArraysInstanced(mode, first, count, instances);
  count_draw();
}

void Context::draw_elements(GLenum mode, GLsizei count, GLenum type, const void* indices) {
  counted_.DrawElements(mode, count, type, indices);
  count_draw();
}

void Context::read_pixels(GLint x, GLint y, GLsizei width, GLsizei height, GLenum format,
                          GLenum type, void* pixels) {
  counted_.ReadPixels(x, y, width, height, format, type, pixels);
  ++draw_counts_.host_read_backs;
}

void Context::copy_pixels_to_buffer(GLuint pack_buffer, GLint x, GLint y, GLsizei width,
                                    GLsizei height, GLenum format, GLenum type, GLintptr offset) {
  gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, pack_buffer);
  // With a pack buffer bound, the pointer argument is the byte offset into it.
  counted_.ReadPixels(x, y, width, height, format, type,
                      reinterpret_cast<void*>(static_cast<std::uintptr_t>(offset)));
  gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  ++draw_counts_.device_copies;
}

// Mapped through the copy targets, which no pixel transfer or draw reads: binding there leaves the
// pack, unpack and array bindings of the strategies alone.
void* Context::map_buffer(GLuint buffer, GLsizeiptr bytes, GLbitfield access,
                          std::string_view where) {
  const GLenum target = (access & GL_MAP_READ_BIT) ? GL_COPY_READ_BUFFER : GL_COPY_WRITE_BUFFER;
  gl_.BindBuffer(target, buffer);
  void* data = counted_.MapBufferRange(target, 0, bytes, access);
  gl_.BindBuffer(target, 0);
  if (!data) {
    check(where);
    throw Error(fmt::format("{} ({}): glMapBufferRange of {} bytes gave no mapping", where,
                            description_, bytes));
  }
  if (access & GL_MAP_READ_BIT) ++draw_counts_.host_read_backs;
  return data;
}

void Context::unmap_buffer(GLuint buffer, std::string_view where) {
  gl_.BindBuffer(GL_COPY_READ_BUFFER, buffer);
  const GLboolean kept = counted_.UnmapBuffer(GL_COPY_READ_BUFFER);
  gl_.BindBuffer(GL_COPY_READ_BUFFER, 0);
  if (!kept)
    throw Error(fmt::format("{} ({}): the buffer's content was lost while it was mapped", where,
                            description_));
}

void Context::read_buffer(GLuint buffer, GLintptr offset, GLsizeiptr bytes, void* data) {
  gl_.BindBuffer(GL_COPY_READ_BUFFER, buffer);
  counted_.GetBufferSubData(GL_COPY_READ_BUFFER, offset, bytes, data);
  gl_.BindBuffer(GL_COPY_READ_BUFFER, 0);
  ++draw_counts_.host_read_backs;
}

void Context::count_draw() {
  ++draw_counts_.draws;
  if (!bound_target_drawn_) ++draw_counts_.passes;
  bound_target_drawn_ = true;
}

bool Context::software() const {
  std::string r = renderer_;
  std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* s : {"llvmpipe", "softpipe", "swrast", "software", "lavapipe"})
    if (r.find(s) != std::string::npos) return true;
  return false;
}

bool Context::has_extension(std::string_view name) const {
  return std::find(extensions_.begin(), extensions_.end(), name) != extensions_.end();
}

DeviceInfo Context::device_info() const {
  DeviceInfo d;
  d.name = renderer_;
  d.kind = software() ? "cpu" : "gpu";
  d.details = {
      {"gl_platform", description_},   {"gl_renderer", renderer_},
      {"gl_vendor", vendor_},          {"gl_version", version_},
      {"glsl_version", glsl_version_}, {"gl_max_texture_size", std::to_string(max_texture_size_)}};
  if (software()) d.details["note"] = "software rasterizer: the 'GPU' is the CPU";
  return d;
}

DeviceTimer::~DeviceTimer() {
  if (!query_) return;
  context_.make_current();
  context_.gl().DeleteQueries(1, &query_);
}

double DeviceTimer::time(std::string_view where, const std::function<void()>& work) {
  context_.make_current();
  const Functions& gl = context_.gl();
  if (!query_) gl.GenQueries(1, &query_);
  gl.BeginQuery(GL_TIME_ELAPSED, query_);
  work();
  gl.EndQuery(GL_TIME_ELAPSED);
  context_.finish(where);
  GLuint64 ns = 0;
  gl.GetQueryObjectui64v(query_, GL_QUERY_RESULT, &ns);
  context_.check(where);
  return static_cast<double>(ns) * 1e-9;
}

void Context::finish(std::string_view where) {
  GLsync fence = gl_.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  if (!fence) throw Error(fmt::format("{} ({}): glFenceSync failed", where, description_));
  const GLenum waited =
      gl_.ClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, device_wait_limit_ns());
  gl_.DeleteSync(fence);
  if (waited == GL_TIMEOUT_EXPIRED)
    throw device_timeout(fmt::format("{} ({}): glClientWaitSync", where, description_));
  if (waited == GL_WAIT_FAILED)
    throw Error(fmt::format("{} ({}): glClientWaitSync failed", where, description_));
}

void Context::check(std::string_view where) {
  std::vector<std::string> errors;
  errors.swap(debug_errors_);
  for (GLenum e = gl_.GetError(); e != GL_NO_ERROR; e = gl_.GetError())
    errors.push_back(fmt::format("{} (0x{:04x})", error_name(e), e));
  if (!errors.empty())
    throw Error(fmt::format("{} ({}): {}", where, description_, fmt::join(errors, "; ")));
}

void APIENTRY debug_message(GLenum /*source*/, GLenum type, GLuint /*id*/, GLenum severity,
                            GLsizei length, const GLchar* message, const void* self) {
  // Called by the driver: record, never throw through it. check() turns these into errors.
  if (type != GL_DEBUG_TYPE_ERROR && severity != GL_DEBUG_SEVERITY_HIGH) return;
  auto* context = const_cast<Context*>(static_cast<const Context*>(self));
  context->debug_errors_.emplace_back(
      length >= 0 ? std::string(message, static_cast<std::size_t>(length)) : std::string(message));
}

}  // namespace nurbs::gl
