#include "strategies/cl_stair/cl_stair.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <optional>
#include <utility>
#include <vector>

#include "reference/nurbs_math.h"
#include "strategies/ksquad/ksquad_table.h"
#include "strategies/opencl/cl_device.h"
#include "strategies/stair_basis/stair.h"
#include "strategies/trim_direct/trim_tables.h"

namespace nurbs::embedded {
extern const std::string_view cl_stair_kernel;
extern const std::string_view cl_stair_basis_header;
extern const std::string_view cl_trim_direct_header;
extern const std::string_view cl_stair_classify_kernel;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

constexpr int kSurfaceInts = 12;  // stair.cl: surfaces record
constexpr int kQuadInts = 8;      // stair.cl: ksquads record
constexpr std::size_t kGroupSize = 64;

struct Program {
  cl_program program = nullptr;
  ~Program() {
    if (program) clReleaseProgram(program);
  }
};

cl_program build_stair(const opencl::Context& ctx, Precision precision) {
  if (precision == Precision::f64 && !ctx.has_fp64())
    throw RefusedError("precision f64: the OpenCL device has no cl_khr_fp64");
  const bool f64 = precision == Precision::f64;
  // The single-source stair basis, then the kernels that use it.
  const std::string source =
      std::string(f64 ? "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n" : "") +
      std::string(embedded::cl_stair_basis_header) + "\n" + std::string(embedded::cl_stair_kernel);
  return ctx.build(
      source, f64 ? "-DSB_REAL=double" : "-DSB_REAL=float -cl-fp32-correctly-rounded-divide-sqrt");
}

// The classify program: the single-source classifier (trim_direct.h) and classify.cl, in the
// precision of the request.
cl_program build_classify(const opencl::Context& ctx, Precision precision) {
  const bool f64 = precision == Precision::f64;
  const std::string source =
      std::string(f64 ? "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n" : "") +
      std::string(embedded::cl_trim_direct_header) + "\n" +
      std::string(embedded::cl_stair_classify_kernel);
  return ctx.build(source, f64 ? "-DTD_REAL=double" : "-DTD_REAL=float");
}

class ClStair final : public Strategy {
 public:
  ClStair(int device_index, const trim_direct::Settings& trim)
      : ctx_(device_index), trim_settings_(trim) {
    record_ = ctx_.record();
    trim_direct::record_settings(trim_settings_, record_);
  }
  ~ClStair() override { release(); }

  std::string_view name() const override { return "cl-stair"; }
  Capabilities capabilities() const override { return cl_stair_descriptor().capabilities; }
  DeviceInfo device() const override { return record_; }

  // The programs are built on the first prepare() of their precision and kept (a JIT build is
  // tens of milliseconds on PoCL, far more than an upload): "program_builds" in the record counts
  // them.
  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    release();
    request_ = request;
    refuse_local_memory(scene);
    samples_ = sample_parameters(scene, request.sampling);
    if (request.precision == Precision::f32) {
      upload<float>(scene);
      upload_trims<float>(scene);
    } else {
      upload<double>(scene);
      upload_trims<double>(scene);
    }
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

  // One launch per trimmed surface over its grid; the mask and the cost counter stay on the device
  // until read_back().
  bool classify() override {
    classified_ = false;
    cl_event last = nullptr;
    for (const TrimLaunch& t : trim_launches_) {
      const std::size_t count = t.nu * t.nv;
      if (count == 0) continue;
      const std::size_t local = std::min(kGroupSize, ctx_.max_work_group());
      const std::size_t global = (count + local - 1) / local * local;
      const cl_int base = t.base, nu = static_cast<cl_int>(t.nu), nv = static_cast<cl_int>(t.nv),
                   iterations = trim_settings_.iterations, out_base = static_cast<cl_int>(t.out);
      cl_mem u = t.u, v = t.v;
      const std::pair<std::size_t, const void*> args[] = {
          {sizeof(cl_mem), &trim_reals_}, {sizeof(cl_mem), &trim_ints_},
          {sizeof(cl_int), &base},        {sizeof(cl_mem), &u},
          {sizeof(cl_int), &nu},          {sizeof(cl_mem), &v},
          {sizeof(cl_int), &nv},          {t.epsilon_bytes.size(), t.epsilon_bytes.data()},
          {sizeof(cl_int), &iterations},  {sizeof(cl_int), &out_base},
          {sizeof(cl_mem), &inside_},     {sizeof(cl_mem), &reads_}};
      for (cl_uint k = 0; k < 12; ++k)
        opencl::check(clSetKernelArg(classify_kernel_, k, args[k].first, args[k].second),
                      "clSetKernelArg (classify_trim)");
      if (last) clReleaseEvent(last);
      last = nullptr;
      opencl::check(clEnqueueNDRangeKernel(ctx_.queue(), classify_kernel_, 1, nullptr, &global,
                                           &local, 0, nullptr, &last),
                    "clEnqueueNDRangeKernel (classify_trim)");
    }
    if (last) {
      opencl::wait(last, "kernel classify_trim");
      clReleaseEvent(last);
    }
    classified_ = true;
    return true;
  }

  EvalResult read_back() override {
    const std::size_t scalar = request_.precision == Precision::f32 ? 4 : 8;
    std::vector<unsigned char> host(total_ * 3 * scalar);
    if (total_ > 0) read_back_s_ = opencl::read(ctx_, out_, host.data(), host.size(), "positions");
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
    if (classified_ && !trim_launches_.empty()) read_back_mask(&out);
    return out;
  }

  // Only the homogeneous control points move (003 §5): the tables, knots, parameters, KSQuads and
  // trims of prepare() stay. The scene must have the prepared scene's surfaces and net sizes.
  void update_control_points(const Scene& scene) override {
    if (request_.precision == Precision::f32)
      write_points<float>(scene);
    else
      write_points<double>(scene);
  }

  DeviceTimes device_times() const override { return {kernel_s_}; }

 private:
  // A program and its one kernel, built once per precision.
  struct Built {
    Program program;
    cl_kernel kernel = nullptr;
    ~Built() {
      if (kernel) clReleaseKernel(kernel);
    }
  };

  // The precision's evaluate_ksquads and classify_trim kernels, building the program on first use.
  cl_kernel stair_kernel(Precision precision) {
    return kernel_of(stair_[precision == Precision::f64], build_stair, precision,
                     "evaluate_ksquads");
  }
  cl_kernel classify_kernel(Precision precision) {
    return kernel_of(classify_[precision == Precision::f64], build_classify, precision,
                     "classify_trim");
  }
  cl_kernel kernel_of(Built& b, cl_program (*build)(const opencl::Context&, Precision),
                      Precision precision, const char* name) {
    if (!b.kernel) {
      b.program.program = build(ctx_, precision);
      ++program_builds_;
      record_.details["program_builds"] = std::to_string(program_builds_);
      cl_int status = CL_SUCCESS;
      b.kernel = clCreateKernel(b.program.program, name, &status);
      opencl::check(status, name);
    }
    return b.kernel;
  }

  // The KSQuad's control points are cached in local memory sized for the scene's largest degrees
  // (evaluate_ksquads' `cp`), beside the kernel's own local arrays (both directions' constants):
  // refused when that exceeds the device's local memory, naming both. PoCL on the CPU and every
  // OpenCL 1.2 full-profile device (>= 32 KiB) fit degree 15 in double (8 KiB + 4.6 KiB).
  void refuse_local_memory(const Scene& scene) {
    int pu = 1, pv = 1;
    for (const Surface& s : scene.surfaces) {
      pu = std::max(pu, s.degree_u);
      pv = std::max(pv, s.degree_v);
    }
    const std::size_t scalar = request_.precision == Precision::f32 ? 4 : 8;
    cp_bytes_ = static_cast<std::size_t>(4 * (pu + 1) * (pv + 1)) * scalar;
    cl_kernel kernel = stair_kernel(request_.precision);
    cl_ulong fixed = 0, available = 0;
    opencl::check(clGetKernelWorkGroupInfo(kernel, ctx_.device(), CL_KERNEL_LOCAL_MEM_SIZE,
                                           sizeof fixed, &fixed, nullptr),
                  "clGetKernelWorkGroupInfo (CL_KERNEL_LOCAL_MEM_SIZE)");
    opencl::check(clGetDeviceInfo(ctx_.device(), CL_DEVICE_LOCAL_MEM_SIZE, sizeof available,
                                  &available, nullptr),
                  "clGetDeviceInfo (CL_DEVICE_LOCAL_MEM_SIZE)");
    // CL_KERNEL_LOCAL_MEM_SIZE counts a __local argument at the size last set: subtract ours.
    const cl_ulong own = fixed >= last_cp_bytes_ ? fixed - last_cp_bytes_ : fixed;
    if (own + cp_bytes_ > available)
      throw RefusedError(fmt::format(
          "cl-stair: degree ({}, {}) in {} needs {} bytes of local memory per work-group (control "
          "point cache {} + stair constants {}), CL_DEVICE_LOCAL_MEM_SIZE is {}",
          pu, pv, to_string(request_.precision), own + cp_bytes_, cp_bytes_, own, available));
    record_.details["local_mem_bytes"] = std::to_string(own + cp_bytes_);
    // Private memory has no device limit to check in OpenCL 1.2 (a GPU spills): recorded only.
    cl_ulong private_bytes = 0;
    opencl::check(clGetKernelWorkGroupInfo(kernel, ctx_.device(), CL_KERNEL_PRIVATE_MEM_SIZE,
                                           sizeof private_bytes, &private_bytes, nullptr),
                  "clGetKernelWorkGroupInfo (CL_KERNEL_PRIVATE_MEM_SIZE)");
    record_.details["private_mem_bytes"] = std::to_string(private_bytes);
  }

  template <typename T>
  void write_points(const Scene& scene) {
    std::vector<T> points;
    for (const Surface& s : scene.surfaces) {
      const SurfaceNet<T> net(s);
      for (const Vec4<T>& h : net.homogeneous) points.insert(points.end(), h.begin(), h.end());
    }
    if (points.size() != points_count_)
      throw std::invalid_argument(fmt::format(
          "cl-stair: update_control_points got {} control point reals, prepare() had {}",
          points.size(), points_count_));
    opencl::write(ctx_, points_, points.data(), points.size() * sizeof(T), "control points");
  }

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
    points_count_ = points.size();
    params_ = upload_buffer(params, "parameters");
    out_ = ctx_.buffer(CL_MEM_WRITE_ONLY, total_ * 3 * sizeof(T), "output positions");
    kernel_ = stair_kernel(request_.precision);
    cl_mem args[] = {surfaces_, quads_buf_, knots_, points_, params_, out_};
    for (cl_uint k = 0; k < 6; ++k)
      opencl::check(clSetKernelArg(kernel_, k, sizeof(cl_mem), &args[k]), "clSetKernelArg");
    opencl::check(clSetKernelArg(kernel_, 6, cp_bytes_, nullptr), "clSetKernelArg (local cache)");
    last_cp_bytes_ = cp_bytes_;
    cl_event uploaded = nullptr;
    opencl::check(clEnqueueMarkerWithWaitList(ctx_.queue(), 0, nullptr, &uploaded),
                  "clEnqueueMarkerWithWaitList");
    opencl::wait(uploaded, "upload");
    clReleaseEvent(uploaded);
  }

  // The direct-trimming tables of the scene and, per trimmed surface, its grid parameters in the
  // trim's local frame (rounded once from double, like the C++ path).
  template <typename T>
  void upload_trims(const Scene& scene) {
    trim_launches_.clear();
    classified_ = false;
    if (std::none_of(scene.surfaces.begin(), scene.surfaces.end(),
                     [](const Surface& s) { return s.trim.has_value(); }))
      return;
    const auto tables = trim_direct::build_tables<T>(scene, trim_settings_);
    classify_kernel_ = classify_kernel(request_.precision);
    trim_reals_ = upload_buffer(tables.reals, "trim tables (reals)");
    trim_ints_ = upload_buffer(tables.ints, "trim tables (ints)");
    std::size_t out = 0;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const auto& st = tables.surfaces[i];
      const SurfaceSamples& sm = samples_[i];
      if (st.base >= 0) {
        TrimLaunch t;
        t.surface = i;
        t.base = st.base;
        t.nu = sm.u.size();
        t.nv = sm.v.size();
        t.out = out;
        std::vector<T> u, v;
        for (double x : sm.u) u.push_back(trim_direct::local_u<T>(st, x));
        for (double x : sm.v) v.push_back(trim_direct::local_v<T>(st, x));
        t.u = upload_buffer(u, "trim local u");
        t.v = upload_buffer(v, "trim local v");
        t.epsilon_bytes.resize(sizeof(T));
        std::memcpy(t.epsilon_bytes.data(), &st.epsilon, sizeof(T));
        out += sm.count();
        trim_launches_.push_back(std::move(t));
      }
    }
    trimmed_samples_ = out;
    inside_ = ctx_.buffer(CL_MEM_WRITE_ONLY, std::max<std::size_t>(out, 1), "trim mask");
    reads_ = ctx_.buffer(CL_MEM_WRITE_ONLY, std::max<std::size_t>(out, 1) * sizeof(cl_int),
                         "trim cost counter");
    record_.details["trim_pieces"] = std::to_string(tables.pieces);
    record_.details["trim_rows"] = std::to_string(tables.rows);
  }

  // The mask into `result` (when given) and the cost counter into the record.
  void read_back_mask(EvalResult* result) {
    std::vector<std::uint8_t> mask(trimmed_samples_);
    std::vector<cl_int> reads(trimmed_samples_);
    opencl::read(ctx_, inside_, mask.data(), mask.size(), "trim mask");
    opencl::read(ctx_, reads_, reads.data(), reads.size() * sizeof(cl_int), "trim cost counter");
    trim_direct::Cost cost;
    for (cl_int r : reads) cost.add(2 * r);
    trim_direct::record_cost(cost, record_);
    if (!result) return;
    for (const TrimLaunch& t : trim_launches_)
      result->surfaces[t.surface].inside.assign(
          mask.begin() + static_cast<std::ptrdiff_t>(t.out),
          mask.begin() + static_cast<std::ptrdiff_t>(t.out + t.nu * t.nv));
  }

  template <typename V>
  cl_mem upload_buffer(const std::vector<V>& data, const char* what) {
    return opencl::upload(ctx_, data, what, &upload_s_);
  }

  // What prepare() made for one scene; the programs and kernels stay (~ClStair releases them).
  void release() {
    kernel_ = nullptr;
    classify_kernel_ = nullptr;
    for (TrimLaunch& t : trim_launches_)
      for (cl_mem m : {t.u, t.v})
        if (m) clReleaseMemObject(m);
    trim_launches_.clear();
    for (cl_mem* m : {&surfaces_, &quads_buf_, &knots_, &points_, &params_, &out_, &trim_reals_,
                      &trim_ints_, &inside_, &reads_}) {
      if (*m) clReleaseMemObject(*m);
      *m = nullptr;
    }
    classified_ = false;
    upload_s_ = 0;
  }

  // One classify launch: a trimmed surface's grid and where its mask starts.
  struct TrimLaunch {
    std::size_t surface = 0, nu = 0, nv = 0, out = 0;
    int base = 0;
    cl_mem u = nullptr, v = nullptr;
    std::vector<unsigned char> epsilon_bytes;  // a float or a double, as the kernel's TD_REAL
  };

  opencl::Context ctx_;
  DeviceInfo record_;
  trim_direct::Settings trim_settings_;
  Built stair_[2], classify_[2];  // [0] f32, [1] f64
  int program_builds_ = 0;
  std::size_t cp_bytes_ = 0, last_cp_bytes_ = 0, points_count_ = 0;
  cl_kernel classify_kernel_ = nullptr;
  cl_mem trim_reals_ = nullptr, trim_ints_ = nullptr, inside_ = nullptr, reads_ = nullptr;
  std::vector<TrimLaunch> trim_launches_;
  std::size_t trimmed_samples_ = 0;
  bool classified_ = false;
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
                                          const std::vector<double>& u, Precision precision,
                                          bool derivative) {
  // One context and one program per precision for all the calls of a test process.
  static opencl::Context ctx(0);
  static Program programs[2];
  Program& program = programs[precision == Precision::f64];
  if (!program.program) program.program = build_stair(ctx, precision);
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
  const cl_int derivative_arg = derivative ? 1 : 0;
  clSetKernelArg(kernel, 6, sizeof(cl_int), &derivative_arg);
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
  return make_entry(cl_stair_descriptor(), opencl::probe,
                    [](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
                      return std::make_unique<ClStair>(
                          opencl::device_option(options),
                          trim_direct::settings_from(options, "cl-stair"));
                    });
}

}  // namespace nurbs
