#include "strategies/cl_stair/cl_stair.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include "reference/nurbs_math.h"
#include "strategies/ksquad/ksquad_table.h"
#include "strategies/opencl/cl_device.h"
#include "strategies/opencl/cl_read_back.h"
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
constexpr int kQuadInts = 8;      // stair.cl: ksquads record (a tile of a KSQuad)
constexpr std::size_t kGroupSize = 64;
// The launch's shape (ClStair::tile_samples): work-groups per compute unit it aims for, and the
// most samples one work-item evaluates.
constexpr std::size_t kGroupsPerUnit = 32;
constexpr std::size_t kMaxSamplesPerItem = 16;

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
  ClStair(int device_index, const trim_direct::Settings& trim, const StrategyOptions& options)
      : ctx_(device_index),
        trim_settings_(trim),
        reader_(ctx_, opencl::read_back_path(ctx_, options)) {
    record_ = ctx_.record();
    trim_direct::record_settings(trim_settings_, record_);
    record_.details["read_back"] = opencl::to_string(reader_.path());
    compute_units_ = std::stoul(record_.details.at("compute_units"));
  }
  ~ClStair() override {
    release();
    for (cl_mem m : {out_, inside_, reads_})
      if (m) clReleaseMemObject(m);
  }

  std::string_view name() const override { return "cl-stair"; }
  Capabilities capabilities() const override { return cl_stair_descriptor().capabilities; }
  // The direct-trimming cost counter is read here, after the harness's timed read-backs, not in
  // each of them: 4 bytes per trimmed sample, more than the mask, for the record only.
  DeviceInfo device() const override {
    if (cost_pending_) record_trim_cost();
    return record_;
  }

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
    record_.details["bytes_uploaded"] = std::to_string(bytes_uploaded_);
    record_.details.erase("bytes_updated");
  }

  // Launch shape: one work-group of kGroupSize work-items per tile of a KSQuad (tile_ksquads), at
  // most tile_samples() samples each, about kGroupsPerUnit groups per compute unit: thousands of
  // groups on a GPU, where one group per KSQuad gave patch144 81 groups on an H200's 132 SMs, each
  // evaluating ~207,000 points at 4096² (evaluate at ~0.2% of the memory bandwidth). On PoCL's two
  // cores the shape makes no measurable difference.
  void evaluate() override {
    if (tiles_ == 0) return;
    cl_event done = nullptr;
    const std::size_t local = std::min(kGroupSize, ctx_.max_work_group());
    const std::size_t global = tiles_ * local;
    opencl::check(clEnqueueNDRangeKernel(ctx_.queue(), kernel_, 1, nullptr, &global, &local, 0,
                                         nullptr, &done),
                  "clEnqueueNDRangeKernel");
    const std::unique_ptr<std::remove_pointer_t<cl_event>, decltype(&clReleaseEvent)> owned(
        done, clReleaseEvent);
    opencl::wait(done, "kernel evaluate_ksquads");
    times_.evaluate_s = opencl::event_seconds(done);
  }

  // One launch per trimmed surface over its grid, waited for once; the mask and the cost counter
  // stay on the device until read_back() (the mask) and device() (the counter).
  bool classify() override {
    classified_ = false;
    opencl::Batch launches;
    for (const TrimLaunch& t : trim_launches_) {
      const std::size_t count = t.nu * t.nv;
      if (count == 0) continue;
      const std::size_t local = std::min(kGroupSize, ctx_.max_work_group());
      const std::size_t global = (count + local - 1) / local * local;
      const cl_int base = t.base, u_base = static_cast<cl_int>(t.u_base),
                   nu = static_cast<cl_int>(t.nu), v_base = static_cast<cl_int>(t.v_base),
                   nv = static_cast<cl_int>(t.nv), iterations = trim_settings_.iterations,
                   out_base = static_cast<cl_int>(t.out);
      const std::pair<std::size_t, const void*> args[] = {
          {sizeof(cl_mem), &trim_reals_},
          {sizeof(cl_mem), &trim_ints_},
          {sizeof(cl_int), &base},
          {sizeof(cl_mem), &trim_params_},
          {sizeof(cl_int), &u_base},
          {sizeof(cl_int), &nu},
          {sizeof(cl_int), &v_base},
          {sizeof(cl_int), &nv},
          {t.epsilon_bytes.size(), t.epsilon_bytes.data()},
          {sizeof(cl_int), &iterations},
          {sizeof(cl_int), &out_base},
          {sizeof(cl_mem), &inside_},
          {sizeof(cl_mem), &reads_}};
      for (cl_uint k = 0; k < 13; ++k)
        opencl::check(clSetKernelArg(classify_kernel_, k, args[k].first, args[k].second),
                      "clSetKernelArg (classify_trim)");
      opencl::check(clEnqueueNDRangeKernel(ctx_.queue(), classify_kernel_, 1, nullptr, &global,
                                           &local, 0, nullptr, launches.next()),
                    "clEnqueueNDRangeKernel (classify_trim)");
    }
    times_.classify_s = launches.wait("kernel classify_trim");
    classified_ = true;
    cost_pending_ = !trim_launches_.empty();
    return true;
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  // Into `out`'s storage (opencl::ResultReader: straight into it, or through the pinned staging
  // area), the positions and, after classify(), the trim masks, in one completion wait.
  void read_back_into(EvalResult& out) override {
    static const std::vector<opencl::MaskPiece> no_masks;
    const bool masks = classified_ && !trim_launches_.empty();
    times_.read_back_s = reader_.read(out, samples_, request_.precision, out_, nullptr, inside_,
                                      masks ? mask_pieces_ : no_masks);
  }

  // Only the homogeneous control points move (003 §5): the tables, knots, parameters, KSQuads and
  // trims of prepare() stay. The scene must have the prepared scene's surfaces and net sizes.
  void update_control_points(const Scene& scene) override {
    if (request_.precision == Precision::f32)
      write_points<float>(scene);
    else
      write_points<double>(scene);
  }

  DeviceTimes device_times() const override { return times_; }

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
    opencl::Batch batch;
    opencl::enqueue_write(batch, ctx_, points_, 0, points.data(), points.size() * sizeof(T),
                          "control points");
    times_.upload_s = batch.wait("control points");
    record_.details["bytes_updated"] = std::to_string(batch.bytes());
  }

  // The work-groups of a launch: each KSQuad cut into tiles of at most `tile` samples -- whole
  // rows of its v-run where they fit (consecutive outputs, coalesced writes), else pieces of one
  // row. A tile is a set of the paper's KSDice (003 §4, the domain shader: one evaluation per
  // sample with the KSQuad's control points and constant denominators); its work-group caches
  // them once, as the one group per KSQuad did, for `tile` samples instead of all of the KSQuad's.
  std::vector<int> tile_ksquads(const std::vector<ksquad::KSQuad>& quads, std::size_t tile) const {
    std::vector<int> tiles;
    const auto add = [&](const ksquad::KSQuad& k, int u_begin, int u_count, int v_begin,
                         int v_count) {
      const int t[kQuadInts] = {k.surface, k.u.span, k.v.span, u_begin,
                                u_count,   v_begin,  v_count,  0};
      tiles.insert(tiles.end(), t, t + kQuadInts);
    };
    for (const ksquad::KSQuad& k : quads) {
      if (k.u.count == 0 || k.v.count == 0) continue;
      const int width = static_cast<int>(std::min<std::size_t>(k.v.count, tile));
      const int rows = static_cast<int>(std::max<std::size_t>(1, tile / width));
      for (int a = 0; a < k.u.count; a += rows)
        for (int b = 0; b < k.v.count; b += width)
          add(k, k.u.begin + a, std::min(rows, k.u.count - a), k.v.begin + b,
              std::min(width, k.v.count - b));
    }
    return tiles;
  }

  // Samples per work-group: enough groups to fill the device (kGroupsPerUnit per compute unit),
  // each work-item evaluating at least one and at most kMaxSamplesPerItem samples (the group's
  // cache of control points and constants is paid once per tile).
  std::size_t tile_samples(std::size_t local) const {
    const std::size_t groups = std::max<std::size_t>(1, compute_units_ * kGroupsPerUnit);
    const std::size_t per_group = (total_ + groups - 1) / groups;
    return std::clamp<std::size_t>(per_group, local, kMaxSamplesPerItem * local);
  }

  template <typename T>
  void upload(const Scene& scene) {
    std::vector<int> surfaces;
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
    total_ = out_base;
    // The host bins parameters by span once; one KSQuad per pair of non-empty runs, cut into tiles.
    const std::size_t local = std::min(kGroupSize, ctx_.max_work_group());
    const auto quads = ksquad::build_ksquads<T>(scene, samples_, request_.sampling);
    const std::size_t tile = tile_samples(local);
    const std::vector<int> tiles = tile_ksquads(quads, tile);
    tiles_ = tiles.size() / kQuadInts;
    record_.details["ksquads"] = std::to_string(quads.size());
    record_.details["work_groups"] = std::to_string(tiles_);
    record_.details["tile_samples"] = std::to_string(tile);
    // Every table is built above, then sent with one write per buffer and one completion wait.
    opencl::Batch batch;
    surfaces_ = opencl::upload(ctx_, surfaces, "surface table", batch);
    tiles_buf_ = opencl::upload(ctx_, tiles, "KSQuad tile table", batch);
    knots_ = opencl::upload(ctx_, knots, "knots", batch);
    points_ = opencl::upload(ctx_, points, "control points", batch);
    points_count_ = points.size();
    params_ = opencl::upload(ctx_, params, "parameters", batch);
    opencl::ensure_buffer(ctx_, &out_, &out_bytes_, CL_MEM_WRITE_ONLY, total_ * 3 * sizeof(T),
                          "output positions");
    kernel_ = stair_kernel(request_.precision);
    cl_mem args[] = {surfaces_, tiles_buf_, knots_, points_, params_, out_};
    for (cl_uint k = 0; k < 6; ++k)
      opencl::check(clSetKernelArg(kernel_, k, sizeof(cl_mem), &args[k]), "clSetKernelArg");
    opencl::check(clSetKernelArg(kernel_, 6, cp_bytes_, nullptr), "clSetKernelArg (local cache)");
    last_cp_bytes_ = cp_bytes_;
    times_.upload_s = times_.upload_s.value_or(0) + batch.wait("upload");
    bytes_uploaded_ += batch.bytes();
  }

  // The direct-trimming tables of the scene and the trimmed surfaces' grid parameters in their
  // trims' local frames (rounded once from double, like the C++ path), all surfaces' in one buffer.
  template <typename T>
  void upload_trims(const Scene& scene) {
    trim_launches_.clear();
    mask_pieces_.clear();
    classified_ = false;
    if (std::none_of(scene.surfaces.begin(), scene.surfaces.end(),
                     [](const Surface& s) { return s.trim.has_value(); }))
      return;
    const auto tables = trim_direct::build_tables<T>(scene, trim_settings_);
    classify_kernel_ = classify_kernel(request_.precision);
    std::vector<T> local;
    std::size_t out = 0;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const auto& st = tables.surfaces[i];
      const SurfaceSamples& sm = samples_[i];
      if (st.base >= 0) {
        TrimLaunch t;
        t.base = st.base;
        t.nu = sm.u.size();
        t.nv = sm.v.size();
        t.out = out;
        t.u_base = local.size();
        for (double x : sm.u) local.push_back(trim_direct::local_u<T>(st, x));
        t.v_base = local.size();
        for (double x : sm.v) local.push_back(trim_direct::local_v<T>(st, x));
        t.epsilon_bytes.resize(sizeof(T));
        std::memcpy(t.epsilon_bytes.data(), &st.epsilon, sizeof(T));
        mask_pieces_.push_back({i, out, sm.count()});
        out += sm.count();
        trim_launches_.push_back(std::move(t));
      }
    }
    trimmed_samples_ = out;
    opencl::Batch batch;
    trim_reals_ = opencl::upload(ctx_, tables.reals, "trim tables (reals)", batch);
    trim_ints_ = opencl::upload(ctx_, tables.ints, "trim tables (ints)", batch);
    trim_params_ = opencl::upload(ctx_, local, "trim local parameters", batch);
    opencl::ensure_buffer(ctx_, &inside_, &inside_bytes_, CL_MEM_WRITE_ONLY,
                          std::max<std::size_t>(out, 1), "trim mask");
    opencl::ensure_buffer(ctx_, &reads_, &reads_bytes_, CL_MEM_WRITE_ONLY,
                          std::max<std::size_t>(out, 1) * sizeof(cl_int), "trim cost counter");
    record_.details["trim_pieces"] = std::to_string(tables.pieces);
    record_.details["trim_rows"] = std::to_string(tables.rows);
    times_.upload_s = times_.upload_s.value_or(0) + batch.wait("upload (trims)");
    bytes_uploaded_ += batch.bytes();
  }

  // The cost counter of the last classify() into the record.
  // The record is read after the timed phases: a counter that cannot be read back is said in the
  // record, not turned into a failed measurement.
  void record_trim_cost() const {
    cost_pending_ = false;
    try {
      cost_reads_.resize(trimmed_samples_);
      opencl::read(ctx_, reads_, cost_reads_.data(), cost_reads_.size() * sizeof(cl_int),
                   "trim cost counter");
      trim_direct::Cost cost;
      for (cl_int r : cost_reads_) cost.add(2 * r);
      trim_direct::record_cost(cost, record_);
    } catch (const std::exception& e) {
      record_.details["trim_cost"] = fmt::format("not read: {}", e.what());
    }
  }

  // What prepare() made for one scene; the programs, kernels and the grown output buffers stay
  // (~ClStair releases them).
  void release() {
    kernel_ = nullptr;
    classify_kernel_ = nullptr;
    trim_launches_.clear();
    mask_pieces_.clear();
    for (cl_mem* m : {&surfaces_, &tiles_buf_, &knots_, &points_, &params_, &trim_reals_,
                      &trim_ints_, &trim_params_}) {
      if (*m) clReleaseMemObject(*m);
      *m = nullptr;
    }
    classified_ = cost_pending_ = false;
    times_.upload_s.reset();
    times_.classify_s.reset();
    times_.read_back_s.reset();
    bytes_uploaded_ = 0;
  }

  // One classify launch: a trimmed surface's grid, where its local parameters start in the
  // parameter buffer and where its mask starts.
  struct TrimLaunch {
    std::size_t nu = 0, nv = 0, u_base = 0, v_base = 0, out = 0;
    int base = 0;
    std::vector<unsigned char> epsilon_bytes;  // a float or a double, as the kernel's TD_REAL
  };

  opencl::Context ctx_;
  mutable DeviceInfo record_;
  trim_direct::Settings trim_settings_;
  opencl::ResultReader reader_;
  std::size_t compute_units_ = 1;
  Built stair_[2], classify_[2];  // [0] f32, [1] f64
  int program_builds_ = 0;
  std::size_t cp_bytes_ = 0, last_cp_bytes_ = 0, points_count_ = 0;
  cl_kernel classify_kernel_ = nullptr;
  cl_mem trim_reals_ = nullptr, trim_ints_ = nullptr, trim_params_ = nullptr, inside_ = nullptr,
         reads_ = nullptr;
  std::size_t inside_bytes_ = 0, reads_bytes_ = 0;
  std::vector<TrimLaunch> trim_launches_;
  std::vector<opencl::MaskPiece> mask_pieces_;
  std::size_t trimmed_samples_ = 0;
  bool classified_ = false;
  mutable bool cost_pending_ = false;
  mutable std::vector<cl_int> cost_reads_;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  cl_kernel kernel_ = nullptr;
  cl_mem surfaces_ = nullptr, tiles_buf_ = nullptr, knots_ = nullptr, points_ = nullptr,
         params_ = nullptr, out_ = nullptr;
  std::size_t out_bytes_ = 0, tiles_ = 0, total_ = 0, bytes_uploaded_ = 0;
  // Profiling events of the phases' last calls (DeviceTimes).
  DeviceTimes times_;  // each phase's last device time (device_times())
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
                          trim_direct::settings_from(options, "cl-stair"), options);
                    });
}

}  // namespace nurbs
