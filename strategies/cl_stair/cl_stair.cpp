#include "strategies/cl_stair/cl_stair.h"

#include <cstring>
#include <optional>

#include "reference/nurbs_math.h"
#include "strategies/cl_stair/stair_basis.h"
#include "strategies/ksquad/ksquad_table.h"
#include "strategies/opencl/cl_device.h"

namespace nurbs::embedded {
extern const std::string_view cl_stair_kernel;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

constexpr int kSurfaceInts = 12;  // stair.cl: surfaces record
constexpr int kQuadInts = 8;      // stair.cl: ksquads record
constexpr std::size_t kGroupSize = 64;

Capabilities stair_capabilities() {
  Capabilities c;
  c.max_degree = kStairMaxDegree;
  c.normals = false;  // positions only, as the paper's pipeline
  c.sampling.explicit_list = false;
  return c;
}

struct Program {
  cl_program program = nullptr;
  ~Program() {
    if (program) clReleaseProgram(program);
  }
};

cl_program build_stair(const opencl::Context& ctx, Precision precision) {
  if (precision == Precision::f64 && !ctx.has_fp64())
    throw RefusedError("precision f64: the OpenCL device has no cl_khr_fp64");
  const std::string options = precision == Precision::f64
                                  ? "-DREAL=double -DSTAIR_FP64"
                                  : "-DREAL=float -cl-fp32-correctly-rounded-divide-sqrt";
  return ctx.build(std::string(embedded::cl_stair_kernel), options);
}

class ClStair final : public Strategy {
 public:
  explicit ClStair(int device_index) : ctx_(device_index) {}
  ~ClStair() override { release(); }

  std::string_view name() const override { return "cl-stair"; }
  Capabilities capabilities() const override { return stair_capabilities(); }
  DeviceInfo device() const override { return ctx_.record(); }

  void prepare(const Scene& scene, const EvalRequest& request) override {
    release();
    refuse_unsupported(name(), capabilities(), scene, request);
    request_ = request;
    program_.program = build_stair(ctx_, request.precision);
    samples_ = sample_parameters(scene, request.sampling);
    if (request.precision == Precision::f32)
      upload<float>(scene);
    else
      upload<double>(scene);
  }

  void evaluate() override {
    if (quads_ == 0) return;
    cl_event done = nullptr;
    const std::size_t local = std::min(kGroupSize, ctx_.max_work_group());
    const std::size_t global = quads_ * local;
    opencl::check(clEnqueueNDRangeKernel(ctx_.queue(), kernel_, 1, nullptr, &global, &local, 0,
                                         nullptr, &done),
                  "clEnqueueNDRangeKernel");
    opencl::wait(done, "kernel evaluate_ksquads");
    kernel_s_ = opencl::event_seconds(done);
    clReleaseEvent(done);
  }

  EvalResult read_back() override {
    const std::size_t scalar = request_.precision == Precision::f32 ? 4 : 8;
    std::vector<unsigned char> host(total_ * 3 * scalar);
    if (total_ > 0) {
      cl_event done = nullptr;
      // Non-blocking and a bounded wait (opencl::wait): a blocking read has no bound.
      opencl::check(clEnqueueReadBuffer(ctx_.queue(), out_, CL_FALSE, 0, host.size(), host.data(),
                                        0, nullptr, &done),
                    "clEnqueueReadBuffer");
      opencl::wait(done, "clEnqueueReadBuffer");
      read_back_s_ = opencl::event_seconds(done);
      clReleaseEvent(done);
    }
    EvalResult out;
    std::size_t base = 0;
    for (const SurfaceSamples& s : samples_) {
      SurfaceResult r;
      r.samples = s;
      r.positions = PointArray(request_.precision, s.count());
      void* dst = request_.precision == Precision::f32 ? static_cast<void*>(r.positions.f32())
                                                       : static_cast<void*>(r.positions.f64());
      std::memcpy(dst, host.data() + base * 3 * scalar, s.count() * 3 * scalar);
      base += s.count();
      out.surfaces.push_back(std::move(r));
    }
    return out;
  }

  DeviceTimes device_times() const override { return {kernel_s_}; }

 private:
  template <typename T>
  void upload(const Scene& scene) {
    std::vector<int> surfaces, quads;
    std::vector<T> knots, points, params;
    std::size_t out_base = 0;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      const SurfaceSamples& sm = samples_[i];
      const std::vector<T> ku(s.knots_u.begin(), s.knots_u.end());
      const std::vector<T> kv(s.knots_v.begin(), s.knots_v.end());
      const int rec[kSurfaceInts] = {s.degree_u,
                                     s.degree_v,
                                     s.count_u,
                                     s.count_v,
                                     static_cast<int>(knots.size()),
                                     static_cast<int>(knots.size() + ku.size()),
                                     static_cast<int>(points.size()),
                                     static_cast<int>(params.size()),
                                     static_cast<int>(params.size() + sm.u.size()),
                                     static_cast<int>(sm.v.size()),
                                     static_cast<int>(out_base),
                                     0};
      surfaces.insert(surfaces.end(), rec, rec + kSurfaceInts);
      knots.insert(knots.end(), ku.begin(), ku.end());
      knots.insert(knots.end(), kv.begin(), kv.end());
      const SurfaceNet<T> net(s);
      for (const Vec4<T>& h : net.homogeneous) points.insert(points.end(), h.begin(), h.end());
      for (double u : sm.u) params.push_back(T(u));
      for (double v : sm.v) params.push_back(T(v));
      out_base += sm.count();
    }
    // The host bins parameters by span once; one KSQuad per pair of non-empty runs.
    for (const ksquad::KSQuad& k : ksquad::build_ksquads<T>(scene, samples_, request_.sampling)) {
      const int q[kQuadInts] = {k.surface, k.u.span,  k.v.span,  k.u.begin,
                                k.u.count, k.v.begin, k.v.count, 0};
      quads.insert(quads.end(), q, q + kQuadInts);
    }
    total_ = out_base;
    quads_ = quads.size() / kQuadInts;
    surfaces_ = upload_buffer(surfaces, "surface table");
    quads_buf_ = upload_buffer(quads, "KSQuad table");
    knots_ = upload_buffer(knots, "knots");
    points_ = upload_buffer(points, "control points");
    params_ = upload_buffer(params, "parameters");
    out_ = ctx_.buffer(CL_MEM_WRITE_ONLY, total_ * 3 * sizeof(T), "output positions");
    cl_int status = CL_SUCCESS;
    kernel_ = clCreateKernel(program_.program, "evaluate_ksquads", &status);
    opencl::check(status, "clCreateKernel");
    cl_mem args[] = {surfaces_, quads_buf_, knots_, points_, params_, out_};
    for (cl_uint k = 0; k < 6; ++k)
      opencl::check(clSetKernelArg(kernel_, k, sizeof(cl_mem), &args[k]), "clSetKernelArg");
    cl_event uploaded = nullptr;
    opencl::check(clEnqueueMarkerWithWaitList(ctx_.queue(), 0, nullptr, &uploaded),
                  "clEnqueueMarkerWithWaitList");
    opencl::wait(uploaded, "upload");
    clReleaseEvent(uploaded);
  }

  template <typename V>
  cl_mem upload_buffer(const std::vector<V>& data, const char* what) {
    const std::size_t bytes = data.size() * sizeof(V);
    cl_mem mem = ctx_.buffer(CL_MEM_READ_ONLY, bytes, what);
    if (bytes > 0) {
      cl_event done = nullptr;
      opencl::check(clEnqueueWriteBuffer(ctx_.queue(), mem, CL_FALSE, 0, bytes, data.data(), 0,
                                         nullptr, &done),
                    "clEnqueueWriteBuffer");
      opencl::wait(done, "clEnqueueWriteBuffer");
      upload_s_ += opencl::event_seconds(done);
      clReleaseEvent(done);
    }
    return mem;
  }

  void release() {
    if (kernel_) clReleaseKernel(kernel_);
    kernel_ = nullptr;
    for (cl_mem* m : {&surfaces_, &quads_buf_, &knots_, &points_, &params_, &out_}) {
      if (*m) clReleaseMemObject(*m);
      *m = nullptr;
    }
    if (program_.program) clReleaseProgram(program_.program);
    program_.program = nullptr;
    upload_s_ = 0;
  }

  opencl::Context ctx_;
  Program program_;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  cl_kernel kernel_ = nullptr;
  cl_mem surfaces_ = nullptr, quads_buf_ = nullptr, knots_ = nullptr, points_ = nullptr,
         params_ = nullptr, out_ = nullptr;
  std::size_t quads_ = 0, total_ = 0;
  std::optional<double> kernel_s_;
  double upload_s_ = 0, read_back_s_ = 0;  // profiling events of upload and read-back
};

}  // namespace

std::vector<double> stair_basis_on_device(int span, int degree, const std::vector<double>& knots,
                                          const std::vector<double>& u, Precision precision) {
  opencl::Context ctx(0);
  Program program{build_stair(ctx, precision)};
  cl_int status = CL_SUCCESS;
  cl_kernel kernel = clCreateKernel(program.program, "stair_basis_test", &status);
  opencl::check(status, "clCreateKernel");
  const std::size_t scalar = precision == Precision::f32 ? 4 : 8;
  auto pack = [&](const std::vector<double>& v) {
    std::vector<unsigned char> bytes(v.size() * scalar);
    for (std::size_t k = 0; k < v.size(); ++k) {
      if (scalar == 4) {
        const float f = static_cast<float>(v[k]);
        std::memcpy(bytes.data() + 4 * k, &f, 4);
      } else {
        std::memcpy(bytes.data() + 8 * k, &v[k], 8);
      }
    }
    return bytes;
  };
  const auto kbytes = pack(knots), ubytes = pack(u);
  const std::size_t out_count = u.size() * (degree + 1);
  cl_mem kb = ctx.buffer(CL_MEM_READ_ONLY, kbytes.size(), "knots");
  cl_mem ub = ctx.buffer(CL_MEM_READ_ONLY, ubytes.size(), "parameters");
  cl_mem ob = ctx.buffer(CL_MEM_WRITE_ONLY, out_count * scalar, "basis");
  clEnqueueWriteBuffer(ctx.queue(), kb, CL_TRUE, 0, kbytes.size(), kbytes.data(), 0, nullptr,
                       nullptr);
  clEnqueueWriteBuffer(ctx.queue(), ub, CL_TRUE, 0, ubytes.size(), ubytes.data(), 0, nullptr,
                       nullptr);
  const int n = static_cast<int>(u.size());
  clSetKernelArg(kernel, 0, sizeof(int), &span);
  clSetKernelArg(kernel, 1, sizeof(int), &degree);
  clSetKernelArg(kernel, 2, sizeof(cl_mem), &kb);
  clSetKernelArg(kernel, 3, sizeof(cl_mem), &ub);
  clSetKernelArg(kernel, 4, sizeof(int), &n);
  clSetKernelArg(kernel, 5, sizeof(cl_mem), &ob);
  const std::size_t local = std::min(kGroupSize, ctx.max_work_group()), global = local;
  opencl::check(
      clEnqueueNDRangeKernel(ctx.queue(), kernel, 1, nullptr, &global, &local, 0, nullptr, nullptr),
      "clEnqueueNDRangeKernel");
  std::vector<unsigned char> out(out_count * scalar);
  opencl::check(
      clEnqueueReadBuffer(ctx.queue(), ob, CL_TRUE, 0, out.size(), out.data(), 0, nullptr, nullptr),
      "clEnqueueReadBuffer");
  clReleaseMemObject(kb);
  clReleaseMemObject(ub);
  clReleaseMemObject(ob);
  clReleaseKernel(kernel);
  std::vector<double> result(out_count);
  for (std::size_t k = 0; k < out_count; ++k) {
    if (scalar == 4) {
      float f;
      std::memcpy(&f, out.data() + 4 * k, 4);
      result[k] = f;
    } else {
      std::memcpy(&result[k], out.data() + 8 * k, 8);
    }
  }
  return result;
}

StrategyEntry cl_stair_entry() {
  return {"cl-stair",
          "003 §3.2 (RPNS 2014): non-recursive stair basis, one work-group per KSQuad",
          "strategy",
          opencl::probe,
          stair_capabilities,
          [](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
            return std::make_unique<ClStair>(opencl::device_option(options));
          }};
}

}  // namespace nurbs
