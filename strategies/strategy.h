// The whole contract between the harness and an evaluation strategy (docs/design.md §The strategy
// interface). A strategy builds and uploads in prepare(), does only the measured work in
// evaluate() (returning when the device is done), and copies results to the host in read_back().
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "reference/point_array.h"
#include "reference/sampling.h"
#include "reference/surface.h"

namespace nurbs {

struct SamplingModes {
  bool grid = true;
  bool span_grid = true;
  bool explicit_list = true;
  bool supports(SamplingMode mode) const {
    return mode == SamplingMode::grid        ? grid
           : mode == SamplingMode::span_grid ? span_grid
                                             : explicit_list;
  }
};

struct Capabilities {
  int max_degree = 15;
  bool rational = true;
  bool normals = true;
  bool fp32 = true;
  bool fp64 = true;
  SamplingModes sampling;
  // The strategy decides where it samples (a tessellator given only a density): its results'
  // SurfaceSamples are what it produced, not sample_parameters(request), and are compared with
  // the reference there.
  bool chooses_own_samples = false;
  // update_control_points() re-uploads moved control points (deforming surfaces, 003 §2). When
  // false (the default update does nothing) the deforming benchmark calls prepare() again each
  // frame and records that phase as "frame_prepare" instead of "frame_update".
  bool updates_control_points = false;
  // The strategy classifies its samples against the surfaces' trimming loops in classify() and
  // returns SurfaceResult::inside for every trimmed surface (the real-CAD issue). A strategy
  // without it still evaluates trimmed scenes; its records say "untrimmed".
  bool trims = false;
  // The strategy evaluates T-spline surfaces (Surface::tspline; 001, the T-spline issue); without
  // it a scene with one is refused. `tspline_only`: it evaluates nothing else (its NURBS
  // counterpart is another strategy), so NURBS scenes are refused instead.
  bool tspline = false;
  bool tspline_only = false;
  bool supports(Precision p) const { return p == Precision::f32 ? fp32 : fp64; }
};

// What the strategy ran on, for the record: "cpu" / "gpu" / "cpu (software rasterizer)" etc. in
// `kind`, free-form key/values (renderer, driver, versions) in `details`.
struct DeviceInfo {
  std::string name;  // e.g. "host CPU", "llvmpipe (LLVM 15.0.6, 256 bits)"
  std::string kind;  // "cpu" or "gpu"; software GPU drivers are "cpu"
  std::map<std::string, std::string> details;
};

struct EvalRequest {
  Sampling sampling;
  Precision precision = Precision::f32;
  bool normals = false;
};

struct SurfaceResult {
  SurfaceSamples samples;  // the parameters the strategy was asked to evaluate
  PointArray positions;
  PointArray normals;  // empty unless requested
  // Strategies that trim (Capabilities::trims), for a trimmed surface: 1 where the strategy
  // classified the sample inside the face, 0 outside; empty otherwise.
  std::vector<std::uint8_t> inside;
};

struct EvalResult {
  std::vector<SurfaceResult> surfaces;
};

// The picture of the last render(), for `run --images DIR`: RGBA8, rows top to bottom (a GL
// strategy flips what glReadPixels gives).
struct RenderedImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;  // width * height * 4
};

// Device-side timings of each phase's last call, where the API has timers (GL GL_TIME_ELAPSED
// queries, Vulkan timestamp queries, OpenCL profiling events), recorded beside the wall clock: a
// phase's wall clock holds the host's part too (submission, waits, copies between host buffers),
// and a verdict about the device's work reads the device's clock. Each is the device time of the
// phase's last call: upload = the transfers of the last prepare() (or update_control_points()),
// read_back = the device-to-host transfers of the last read_back(); nullopt where not measured.
struct DeviceTimes {
  std::optional<double> evaluate_s;
  std::optional<double> upload_s;
  std::optional<double> classify_s;
  std::optional<double> render_s;
  std::optional<double> read_back_s;
};

class Strategy {
 public:
  virtual ~Strategy() = default;
  virtual std::string_view name() const = 0;
  virtual Capabilities capabilities() const = 0;
  virtual DeviceInfo device() const = 0;
  // Refuses what capabilities() rules out (RefusedError, the rule of refusal_reason()), then
  // calls the strategy's own prepare_checked(): every strategy meets the same check whoever calls
  // it, the harness or a test or a user's program, and none can forget it.
  void prepare(const Scene& scene, const EvalRequest& request);
  virtual void evaluate() = 0;
  virtual EvalResult read_back() = 0;
  // read_back() into `out`, which holds the previous read back of this request (or is empty): the
  // harness's repetitions pass the same result, so a strategy that copies into out's buffers
  // (copy-assigning vectors of the same size, PointArray::reset) pays its bytes, not a fresh
  // allocation's page faults, on every repetition after the first. The default gives a new
  // result, as read_back() does.
  virtual void read_back_into(EvalResult& out) { out = read_back(); }
  virtual void update_control_points(const Scene&) {}
  virtual DeviceTimes device_times() const { return {}; }
  // Strategies that can draw what they evaluated into an offscreen image (returning when the
  // device is done), timed by the runner as extra phases: `render` draws from where evaluate()
  // left the results, without reading them back (002 §4.2); `render_via_read_back` is the
  // traditional path it is compared with (read back, upload as vertex buffers, draw; 002 §4.1).
  // Each returns false when the strategy has no such path.
  virtual bool render() { return false; }
  // Strategies that trim: classify the samples of the last evaluate() against the trimming loops
  // (returning when the device is done), timed by the runner as its own phase ("classify") and
  // returned by read_back() as SurfaceResult::inside. Called after evaluate() and before
  // read_back(); returns false when the strategy does not trim.
  virtual bool classify() { return false; }
  virtual bool render_via_read_back() { return false; }
  // What the last render() drew (outside-the-trim fragments discarded for trimmed surfaces), read
  // back untimed; nullopt when the strategy does not draw or has not drawn yet.
  virtual std::optional<RenderedImage> last_render() { return std::nullopt; }

 protected:
  // prepare() once the request is known to be within capabilities(): builds and uploads.
  virtual void prepare_checked(const Scene& scene, const EvalRequest& request) = 0;
};

// One surface's read back into `out`, reusing its storage (copy-assigning a vector of the same size
// does not allocate): the body of a host strategy's read_back_into. `inside`: the trim mask, or
// nullptr for none.
inline void copy_surface_into(SurfaceResult& out, const SurfaceSamples& samples,
                              const PointArray& positions, const PointArray& normals,
                              const std::vector<std::uint8_t>* inside = nullptr) {
  out.samples = samples;
  out.positions = positions;
  out.normals = normals;
  if (inside)
    out.inside = *inside;
  else
    out.inside.clear();
}

// Options a user can pass to any strategy's factory; each strategy reads what concerns it.
struct StrategyOptions {
  int threads = 0;  // 0: every core
  std::map<std::string, std::string> extra;
};

// A strategy that cannot run here says why; this is a result, not a crash.
struct Availability {
  bool available = false;
  std::string reason;  // empty when available
};

// A strategy's request is refused before it runs (unsupported degree, sampling, precision...).
class RefusedError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::string sampling_mode_name(SamplingMode mode);

// Why `request` on `scene` is outside what a strategy with `caps` can do, if it is. The harness
// asks before it runs a strategy; Strategy::prepare() calls refuse_unsupported() so a direct
// caller meets the same rule, stated once.
std::optional<std::string> refusal_reason(const Capabilities& caps, const Scene& scene,
                                          const EvalRequest& request);
// Whether a refusal's reason is the scene's kind (a T-spline met by a NURBS-only strategy, or a
// NURBS surface by a T-spline-only one): refused by design, not a missing feature.
bool is_kind_refusal(std::string_view reason);
// Throws RefusedError("<strategy>: <reason>") when refusal_reason() gives one.
void refuse_unsupported(std::string_view strategy, const Capabilities& caps, const Scene& scene,
                        const EvalRequest& request);

}  // namespace nurbs
