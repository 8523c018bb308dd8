#include "strategies/cl_tspline_bezier/cl_tspline_bezier.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/tspline.h"
#include "reference/tspline_extraction.h"
#include "strategies/opencl/cl_device.h"
#include "strategies/opencl/cl_read_back.h"

namespace nurbs::embedded {
extern const std::string_view cl_tspline_bezier_kernel;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

constexpr int kSurfaceLongs = 12;  // tspline_bezier.cl: surfaces record
constexpr int kElementLongs = 5;   // tspline_bezier.cl: elements record

cl_program build_program(const opencl::Context& ctx, Precision precision) {
  if (precision == Precision::f64 && !ctx.has_fp64())
    throw RefusedError("precision f64: the OpenCL device has no cl_khr_fp64");
  const bool f64 = precision == Precision::f64;
  const std::string source =
      std::string(f64 ? "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n" : "") +
      std::string(embedded::cl_tspline_bezier_kernel);
  // Correctly rounded float division and sqrt: the local parameter and the rational division
  // are then within the error bounds the tests derive (OpenCL allows 2.5 ulp otherwise).
  return ctx.build(source, fmt::format("-DMAX_ORDER={} {}", kMaxOrder,
                                       f64 ? "-DREAL=double -DEPSILON=DBL_EPSILON"
                                           : "-DREAL=float -DEPSILON=FLT_EPSILON "
                                             "-cl-fp32-correctly-rounded-divide-sqrt"));
}

// What prepare() derives from a surface's topology (knots, degrees, domain) and keeps for
// update_control_points(): the influence index and its Bézier extraction.
struct Topology {
  std::shared_ptr<const TSplineSurface> tspline;
  TSplineInfluence index;
  TSplineExtraction extraction;
};

class ClTSplineBezier final : public Strategy {
 public:
  ClTSplineBezier(int device_index, const StrategyOptions& options)
      : ctx_(device_index), reader_(ctx_, opencl::read_back_path(ctx_, options)) {
    record_ = ctx_.record();
    record_.details["read_back"] = opencl::to_string(reader_.path());
  }
  ~ClTSplineBezier() override {
    release();
    for (cl_mem m : {patches_, positions_, normals_})
      if (m) clReleaseMemObject(m);
  }

  std::string_view name() const override { return "cl-tspline-bezier"; }
  Capabilities capabilities() const override { return cl_tspline_bezier_descriptor().capabilities; }
  DeviceInfo device() const override { return record_; }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    release();
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    // Every prepare() extracts again rather than caching by topology across calls: `upload` is
    // then what a new model costs (its median would otherwise hide the extraction), and
    // "extraction_s" says how much of it is this host work.
    const auto start = std::chrono::steady_clock::now();
    topology_.clear();
    for (const Surface& s : scene.surfaces) {
      TSplineInfluence index(*s.tspline, s.name);
      TSplineExtraction extraction = extract_bezier_elements(*s.tspline, index);
      topology_.push_back({s.tspline, std::move(index), std::move(extraction)});
    }
    record_.details["extraction_s"] = fmt::format(
        "{:.6g}", std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (request.precision == Precision::f32)
      upload<float>();
    else
      upload<double>();
    record_.details["bytes_uploaded"] = std::to_string(bytes_uploaded_);
    record_.details.erase("bytes_updated");
    decompose();
  }

  void evaluate() override {
    if (total_ == 0) return;
    cl_event done = nullptr;
    const std::size_t global = total_;
    opencl::check(clEnqueueNDRangeKernel(ctx_.queue(), program().evaluate, 1, nullptr, &global,
                                         nullptr, 0, nullptr, &done),
                  "clEnqueueNDRangeKernel (evaluate_samples)");
    const std::unique_ptr<std::remove_pointer_t<cl_event>, decltype(&clReleaseEvent)> owned(
        done, clReleaseEvent);
    opencl::wait(done, "kernel evaluate_samples");
    times_.evaluate_s = opencl::event_seconds(done);
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  // Into `out`'s storage (opencl::ResultReader: straight into it, or through the pinned staging
  // area), positions and normals in one completion wait.
  void read_back_into(EvalResult& out) override {
    times_.read_back_s = reader_.read(out, samples_, request_.precision, positions_,
                                      request_.normals ? normals_ : nullptr, nullptr, {});
  }

  // Only the control points move: the operators, CSR lists, breaks and parameters of prepare()
  // stay, and decompose_elements reruns. A scene of another topology is an error, not a silent
  // evaluation with stale operators.
  void update_control_points(const Scene& scene) override {
    if (scene.surfaces.size() != topology_.size())
      throw std::invalid_argument(
          fmt::format("cl-tspline-bezier: update_control_points got {} surfaces, prepare() had {}",
                      scene.surfaces.size(), topology_.size()));
    for (std::size_t i = 0; i < topology_.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      if (!s.is_tspline() || !same_extraction_topology(*s.tspline, *topology_[i].tspline))
        throw std::invalid_argument(fmt::format(
            "cl-tspline-bezier: update_control_points: surface {} ('{}') is not the prepared "
            "T-spline's topology (degrees, domain, local knot vectors)",
            i, s.name));
      topology_[i].tspline = s.tspline;
    }
    if (request_.precision == Precision::f32)
      write_points<float>();
    else
      write_points<double>();
    decompose();
  }

  DeviceTimes device_times() const override { return times_; }

 private:
  struct Built {
    cl_program program = nullptr;
    cl_kernel decompose = nullptr, evaluate = nullptr;
    ~Built() {
      for (cl_kernel k : {decompose, evaluate})
        if (k) clReleaseKernel(k);
      if (program) clReleaseProgram(program);
    }
  };

  // The request's precision's program, built on first use and kept (a JIT build costs far more
  // than an upload on PoCL): "program_builds" in the record counts them.
  Built& program() {
    Built& b = built_[request_.precision == Precision::f64];
    if (!b.program) {
      b.program = build_program(ctx_, request_.precision);
      ++program_builds_;
      record_.details["program_builds"] = std::to_string(program_builds_);
      cl_int status = CL_SUCCESS;
      b.decompose = clCreateKernel(b.program, "decompose_elements", &status);
      opencl::check(status, "clCreateKernel (decompose_elements)");
      b.evaluate = clCreateKernel(b.program, "evaluate_samples", &status);
      opencl::check(status, "clCreateKernel (evaluate_samples)");
    }
    return b;
  }

  // (x, y, z, w) of every surface's control points, Cartesian: decompose_elements forms
  // w (P - o) against each element's origin o (tspline_bezier.cl).
  template <typename T>
  std::vector<T> control_points() const {
    std::vector<T> points;
    for (const Topology& t : topology_)
      for (std::size_t k = 0; k < t.tspline->count(); ++k) {
        const Point3& p = t.tspline->points[k];
        for (double x : {p[0], p[1], p[2], t.tspline->weights[k]}) points.push_back(T(x));
      }
    return points;
  }

  template <typename T>
  void upload() {
    std::vector<cl_long> surfaces, elements;
    std::vector<cl_int> active, cells;
    std::vector<T> extraction, params, breaks;
    cl_long point_base = 0, patch_reals = 0, out_base = 0;
    for (std::size_t i = 0; i < topology_.size(); ++i) {
      const Topology& t = topology_[i];
      const SurfaceSamples& sm = samples_[i];
      const int p = t.extraction.degree_u, q = t.extraction.degree_v;
      const cl_long n = static_cast<cl_long>(p + 1) * (q + 1);
      const cl_long param_base = static_cast<cl_long>(params.size());
      const cl_long breaks_base = static_cast<cl_long>(breaks.size());
      const cl_long patch_base = patch_reals;
      for (const BezierElement& e : t.extraction.elements) {
        const cl_long record[kElementLongs] = {
            static_cast<cl_long>(active.size()), static_cast<cl_long>(e.functions.size()),
            static_cast<cl_long>(extraction.size()), patch_reals, n};
        elements.insert(elements.end(), record, record + kElementLongs);
        for (int f : e.functions) active.push_back(static_cast<cl_int>(point_base + f));
        for (long double c : e.extraction) extraction.push_back(T(c));
        patch_reals += 4 * (n + 1);  // the origin, then Q
      }
      for (double b : t.index.breaks_u()) breaks.push_back(T(b));
      for (double b : t.index.breaks_v()) breaks.push_back(T(b));
      // The reference's cell rule and the local parameter, in double (see cl_tspline_bezier.h).
      const auto add = [&](double x, int cell, const std::vector<double>& b) {
        cells.push_back(cell);
        params.push_back(T((x - b[cell]) / (b[cell + 1] - b[cell])));
      };
      for (double u : sm.u) add(u, t.index.cell_u(u), t.index.breaks_u());
      for (double v : sm.v) add(v, t.index.cell_v(v), t.index.breaks_v());
      const cl_long record[kSurfaceLongs] = {p,
                                             q,
                                             sm.tensor ? 1 : 0,
                                             static_cast<cl_long>(sm.u.size()),
                                             static_cast<cl_long>(sm.v.size()),
                                             param_base,
                                             breaks_base,
                                             t.index.cells_u(),
                                             t.index.cells_v(),
                                             patch_base,
                                             out_base,
                                             0};
      surfaces.insert(surfaces.end(), record, record + kSurfaceLongs);
      point_base += static_cast<cl_long>(t.tspline->count());
      out_base += static_cast<cl_long>(sm.count());
    }
    total_ = static_cast<std::size_t>(out_base);
    element_count_ = elements.size() / kElementLongs;
    max_n_ = 1;
    for (const Topology& t : topology_)
      max_n_ = std::max<std::size_t>(max_n_, static_cast<std::size_t>(t.extraction.degree_u + 1) *
                                                 (t.extraction.degree_v + 1));
    const std::vector<T> points = control_points<T>();
    points_count_ = points.size();
    // Every surface's tables are built above, then sent with one write per buffer and one
    // completion wait (the batch's wait, at the end of this function, before the vectors go).
    opencl::Batch batch;
    surfaces_ = opencl::upload(ctx_, surfaces, "surface table", batch);
    elements_ = opencl::upload(ctx_, elements, "element table", batch);
    active_ = opencl::upload(ctx_, active, "active control points", batch);
    extraction_ = opencl::upload(ctx_, extraction, "extraction operators", batch);
    points_ = opencl::upload(ctx_, points, "control points", batch);
    params_ = opencl::upload(ctx_, params, "parameters", batch);
    cells_ = opencl::upload(ctx_, cells, "sample elements", batch);
    breaks_ = opencl::upload(ctx_, breaks, "cell breaks", batch);
    // The device-written buffers are kept across prepare() calls and grown when too small.
    opencl::ensure_buffer(ctx_, &patches_, &patches_bytes_, CL_MEM_READ_WRITE,
                          static_cast<std::size_t>(patch_reals) * sizeof(T), "Bézier patches");
    opencl::ensure_buffer(ctx_, &positions_, &positions_bytes_, CL_MEM_WRITE_ONLY,
                          total_ * 3 * sizeof(T), "output positions");
    if (request_.normals)
      opencl::ensure_buffer(ctx_, &normals_, &normals_bytes_, CL_MEM_WRITE_ONLY,
                            total_ * 3 * sizeof(T), "output normals");
    else if (!normals_)
      opencl::ensure_buffer(ctx_, &normals_, &normals_bytes_, CL_MEM_WRITE_ONLY, 0,
                            "output normals");
    record_.details["elements"] = std::to_string(element_count_);
    record_.details["extraction_reals"] = std::to_string(extraction.size());

    Built& b = program();
    const cl_mem decompose_args[] = {elements_, active_, extraction_, points_, patches_};
    for (cl_uint k = 0; k < 5; ++k)
      opencl::check(clSetKernelArg(b.decompose, k, sizeof(cl_mem), &decompose_args[k]),
                    "clSetKernelArg (decompose_elements)");
    const cl_int surface_count = static_cast<cl_int>(topology_.size());
    const cl_long total = out_base;
    const cl_int normals = request_.normals ? 1 : 0;
    const std::pair<std::size_t, const void*> args[] = {
        {sizeof(cl_mem), &surfaces_},  {sizeof(cl_int), &surface_count},
        {sizeof(cl_mem), &params_},    {sizeof(cl_mem), &cells_},
        {sizeof(cl_mem), &breaks_},    {sizeof(cl_mem), &patches_},
        {sizeof(cl_long), &total},     {sizeof(cl_int), &normals},
        {sizeof(cl_mem), &positions_}, {sizeof(cl_mem), &normals_}};
    for (cl_uint k = 0; k < 10; ++k)
      opencl::check(clSetKernelArg(b.evaluate, k, args[k].first, args[k].second),
                    "clSetKernelArg (evaluate_samples)");
    times_.upload_s = batch.wait("upload");
    bytes_uploaded_ = batch.bytes();
  }

  // Every element's Bézier patch from the current control points, waited for: prepare() and
  // update_control_points() include it, evaluate() does not.
  void decompose() {
    if (element_count_ == 0) return;
    const std::size_t global[2] = {max_n_, element_count_};
    cl_event done = nullptr;
    opencl::check(clEnqueueNDRangeKernel(ctx_.queue(), program().decompose, 2, nullptr, global,
                                         nullptr, 0, nullptr, &done),
                  "clEnqueueNDRangeKernel (decompose_elements)");
    const std::unique_ptr<std::remove_pointer_t<cl_event>, decltype(&clReleaseEvent)> owned(
        done, clReleaseEvent);
    opencl::wait(done, "kernel decompose_elements");
    record_.details["decompose_s"] = fmt::format("{:.6g}", opencl::event_seconds(done));
  }

  template <typename T>
  void write_points() {
    const std::vector<T> points = control_points<T>();
    if (points.size() != points_count_)
      throw std::invalid_argument(fmt::format(
          "cl-tspline-bezier: update_control_points got {} control point reals, prepare() had {}",
          points.size(), points_count_));
    opencl::Batch batch;
    opencl::enqueue_write(batch, ctx_, points_, 0, points.data(), points.size() * sizeof(T),
                          "control points");
    times_.upload_s = batch.wait("control points");
    record_.details["bytes_updated"] = std::to_string(batch.bytes());
  }

  // What prepare() made for one scene; the programs (~Built) and the grown device-written buffers
  // (~ClTSplineBezier) stay.
  void release() {
    for (cl_mem* m :
         {&surfaces_, &elements_, &active_, &extraction_, &points_, &params_, &cells_, &breaks_}) {
      if (*m) clReleaseMemObject(*m);
      *m = nullptr;
    }
    total_ = element_count_ = points_count_ = bytes_uploaded_ = 0;
    times_.upload_s.reset();
    times_.read_back_s.reset();
  }

  opencl::Context ctx_;
  DeviceInfo record_;
  opencl::ResultReader reader_;
  Built built_[2];  // [0] f32, [1] f64
  int program_builds_ = 0;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::vector<Topology> topology_;
  cl_mem surfaces_ = nullptr, elements_ = nullptr, active_ = nullptr, extraction_ = nullptr,
         points_ = nullptr, params_ = nullptr, cells_ = nullptr, breaks_ = nullptr,
         patches_ = nullptr, positions_ = nullptr, normals_ = nullptr;
  std::size_t patches_bytes_ = 0, positions_bytes_ = 0, normals_bytes_ = 0;
  std::size_t total_ = 0, element_count_ = 0, max_n_ = 1, points_count_ = 0, bytes_uploaded_ = 0;
  // Profiling events of the phases' last calls (DeviceTimes).
  DeviceTimes times_;  // each phase's last device time (device_times())
};

}  // namespace

StrategyEntry cl_tspline_bezier_entry() {
  return make_entry(cl_tspline_bezier_descriptor(), opencl::probe,
                    [](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
                      return std::make_unique<ClTSplineBezier>(opencl::device_option(options),
                                                               options);
                    });
}

}  // namespace nurbs
