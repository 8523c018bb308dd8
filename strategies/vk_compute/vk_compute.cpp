#include "strategies/vk_compute/vk_compute.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <map>
#include <memory>
#include <stdexcept>
#include <tuple>
#include <variant>

#include "reference/nurbs_math.h"
#include "strategies/host_results.h"
#include "strategies/trim_direct/trim_tables.h"
#include "strategies/vk_compute/layout.h"
#include "strategies/vk_compute/tensor_basis.h"
#include "strategies/vulkan/vk_device.h"
#include "strategies/vulkan/vk_trim_classify.h"

namespace nurbs::embedded {
extern const std::string_view vk_compute_basis_f32_comp;
extern const std::string_view vk_compute_basis_f64_comp;
extern const std::string_view vk_compute_eval_f32_comp;
extern const std::string_view vk_compute_eval_f64_comp;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

using vulkan::Buffer;
using vulkan::memory_barrier;

static_assert(kMaxOrder == TB_MAX_ORDER, "tensor_basis.h's degree bound is the validation's");

// The shaders' bindings (layout.glsl), all storage buffers read or written by the compute stage.
constexpr int kBindings = 10;

struct Launch {
  std::int32_t count = 0, normals = 0, paired = 0, tiles_x = 1, params = 0;
};

vulkan::Requirements compute_requirements() {
  vulkan::Requirements r;
  r.float64_when_present = true;
  return r;
}

// Invocations per work-group: four subgroups (Vulkan 1.1's subgroupSize: 8 on lavapipe with AVX2,
// 32 on NVIDIA, 32/64 on AMD), within maxComputeWorkGroupInvocations and maxComputeWorkGroupSize.
// Few subgroups per group because a tile's invocations loop over its samples anyway, and lavapipe
// runs each subgroup of a group with a barrier as a coroutine of its own, a cost per subgroup and
// group: many-1024 at 32^2 took 392, 543 and 587 ms in groups of 256 invocations against 103, 123
// and 211 ms in groups of 32 (three pairs of runs, 2-core EPYC shared with other jobs: figures
// move by 2x between runs). On patch144 1024^2 the two were within that noise.
std::uint32_t workgroup_size(const vulkan::Device& device, std::uint32_t cap) {
  VkPhysicalDeviceSubgroupProperties subgroup{};
  subgroup.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceProperties2 properties{};
  properties.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  properties.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(device.physical(), &properties);
  const VkPhysicalDeviceLimits& limits = device.limits();
  const std::uint32_t wanted = cap > 0 ? cap : 4 * std::max(subgroup.subgroupSize, 1u);
  return std::min(
      {limits.maxComputeWorkGroupInvocations, limits.maxComputeWorkGroupSize[0], wanted});
}

// Curve points per shared-memory tile: the device's shared memory over the two arrays (values
// and u derivatives) of homogeneous points of `real_bytes` reals.
std::uint32_t tile_points(const VkPhysicalDeviceLimits& limits, std::uint32_t real_bytes) {
  return limits.maxComputeSharedMemorySize / (2 * 4 * real_bytes);
}

// Rows per tile at most. A work-group pays a fixed cost on lavapipe (patch144 1024^2, groups of
// 256: 4096 tiles of one row 1.0 s, 8 rows 180-200 ms, 64 rows 120-140 ms, up to 146 rows (what
// shared memory holds) 70-100 ms), so a tile takes as many rows as shared memory holds up to this
// many, which still leaves a 1024^2 grid over a hundred groups for a GPU's compute units.
constexpr std::uint32_t kMaxTileRows = 64;

// Everything one prepare() uploads, at the evaluation's scalar T.
template <typename T>
struct Tables {
  std::vector<T> knots, params, nets;
  std::vector<std::int32_t> param_axes, surfaces, tiles;
  std::vector<SurfaceNet<T>> host_nets;  // the normals' host fallback
};

template <typename T>
std::vector<T> homogeneous_nets(const Scene& scene) {
  std::vector<T> out;
  for (const Surface& s : scene.surfaces) {
    const SurfaceNet<T> net(s);
    for (const Vec4<T>& h : net.homogeneous) out.insert(out.end(), h.begin(), h.end());
  }
  return out;
}

template <typename T>
class TableBuilder {
 public:
  TableBuilder(std::uint32_t group, std::uint32_t tile, std::uint32_t rows)
      : group_(int(group)), tile_(int(tile)), row_cap_(int(rows)) {}

  Tables<T> build(const Scene& scene, const std::vector<SurfaceSamples>& samples) {
    Tables<T> t;
    t.nets = homogeneous_nets<T>(scene);
    std::int32_t net = 0, out = 0;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      SurfaceNet<T>& host = t.host_nets.emplace_back(s);
      const std::int32_t knots_u = add_knots(t, host.knots_u);
      const std::int32_t knots_v = add_knots(t, host.knots_v);
      const SurfaceSamples& ss = samples[i];
      const std::int32_t u_params =
          add_params(t, knots_u, host.degree_u, host.count_u, host.knots_u, ss.u);
      const std::int32_t v_params =
          add_params(t, knots_v, host.degree_v, host.count_v, host.knots_v, ss.v);
      std::int32_t row[TC_SURFACE_INTS] = {};
      row[TC_S_NET] = net;
      row[TC_S_COUNT_U] = host.count_u;
      row[TC_S_COUNT_V] = host.count_v;
      row[TC_S_DEGREE_U] = host.degree_u;
      row[TC_S_DEGREE_V] = host.degree_v;
      row[TC_S_U_PARAMS] = u_params;
      row[TC_S_V_PARAMS] = v_params;
      row[TC_S_NV] = static_cast<std::int32_t>(ss.v.size());
      row[TC_S_OUT] = out;
      row[TC_S_KNOTS_U] = knots_u;
      row[TC_S_KNOTS_V] = knots_v;
      t.surfaces.insert(t.surfaces.end(), row, row + TC_SURFACE_INTS);
      if (ss.tensor)
        add_grid_tiles(t, static_cast<int>(i), host, ss);
      else
        add_list_tiles(t, static_cast<int>(i), static_cast<int>(ss.u.size()));
      net += host.count_u * host.count_v;
      out += static_cast<std::int32_t>(ss.count());
    }
    return t;
  }

 private:
  static std::int32_t add_knots(Tables<T>& t, const std::vector<T>& knots) {
    const auto at = static_cast<std::int32_t>(t.knots.size());
    t.knots.insert(t.knots.end(), knots.begin(), knots.end());
    return at;
  }

  // The index of the list's first parameter; a list already added for the same knots and degree
  // is shared (many small faces sampled alike pay for one basis table, as in cpu-tensor).
  std::int32_t add_params(Tables<T>& t, std::int32_t knot_offset, int degree, int count,
                          const std::vector<T>& knots, const std::vector<double>& samples) {
    // Parameters rounded to T as the device holds them (cpu-tensor, cpu-coxdeboor too).
    std::vector<T> params(samples.begin(), samples.end());
    auto key = std::make_tuple(degree, knots, params);
    if (const auto it = lists_.find(key); it != lists_.end()) return it->second;
    const auto at = static_cast<std::int32_t>(t.params.size());
    t.params.insert(t.params.end(), params.begin(), params.end());
    for (std::size_t k = 0; k < params.size(); ++k)
      t.param_axes.insert(t.param_axes.end(), {knot_offset, degree, count});
    lists_.emplace(std::move(key), at);
    return at;
  }

  // Tiles of a tensor grid: column runs of at most one work-group whose curve points (the spans'
  // range plus q) fit the shared-memory tile, each with as many rows as the work-group and the
  // tile hold. The spans are the device's own (tensor_basis.h compiled as C++ on the same T
  // values: exact comparisons give the same span); only the layout uses them here.
  void add_grid_tiles(Tables<T>& t, int surface, const SurfaceNet<T>& net,
                      const SurfaceSamples& ss) {
    const int nu = static_cast<int>(ss.u.size()), nv = static_cast<int>(ss.v.size());
    const int q = net.degree_v;
    std::vector<int> spans(nv);
    for (int b = 0; b < nv; ++b)
      spans[b] = tb_find_span(q, net.count_v, net.knots_v.data(), static_cast<T>(ss.v[b]));
    for (int b = 0; b < nv;) {
      int lo = spans[b], hi = spans[b], cols = 1;
      while (b + cols < nv && cols < group_) {
        const int s = spans[b + cols];
        const int nlo = std::min(lo, s), nhi = std::max(hi, s);
        if (nhi - nlo + q + 1 > tile_) break;
        lo = nlo;
        hi = nhi;
        ++cols;
      }
      const int width = hi - lo + q + 1;
      const int rows = std::max(1, std::min(row_cap_, tile_ / width));
      for (int a0 = 0; a0 < nu; a0 += rows) {
        std::int32_t tile[TC_TILE_INTS] = {};
        tile[TC_T_SURFACE] = surface;
        tile[TC_T_A0] = a0;
        tile[TC_T_ROWS] = std::min(rows, nu - a0);
        tile[TC_T_B0] = b;
        tile[TC_T_COLS] = cols;
        tile[TC_T_FIRST_V] = lo - q;
        tile[TC_T_WIDTH] = width;
        t.tiles.insert(t.tiles.end(), tile, tile + TC_TILE_INTS);
      }
      b += cols;
    }
  }

  void add_list_tiles(Tables<T>& t, int surface, int count) {
    for (int k0 = 0; k0 < count; k0 += group_) {
      std::int32_t tile[TC_TILE_INTS] = {};
      tile[TC_T_SURFACE] = surface;
      tile[TC_T_ROWS] = 1;
      tile[TC_T_B0] = k0;
      tile[TC_T_COLS] = std::min(group_, count - k0);
      t.tiles.insert(t.tiles.end(), tile, tile + TC_TILE_INTS);
    }
  }

  int group_, tile_, row_cap_;
  std::map<std::tuple<int, std::vector<T>, std::vector<T>>, std::int32_t> lists_;
};

// Work-groups for `groups` as a 2D grid within maxComputeWorkGroupCount: {x, y}.
std::array<std::uint32_t, 2> grid_of(std::uint32_t groups, const VkPhysicalDeviceLimits& limits) {
  const std::uint32_t x =
      std::max(std::uint32_t{1}, std::min(groups, limits.maxComputeWorkGroupCount[0]));
  const std::uint32_t y = (groups + x - 1) / x;
  if (y > limits.maxComputeWorkGroupCount[1])
    throw RefusedError(
        fmt::format("vk-compute: {} work-groups exceed maxComputeWorkGroupCount", groups));
  return {x, std::max(y, std::uint32_t{1})};
}

class VkCompute final : public Strategy {
 public:
  VkCompute(int device_index, const trim_direct::Settings& trim, std::uint32_t tile_cap,
            std::uint32_t group_cap, std::uint32_t row_cap)
      : device_(device_index, compute_requirements()),
        set_(device_, std::vector<VkShaderStageFlags>(kBindings, VK_SHADER_STAGE_COMPUTE_BIT)),
        queries_(device_, 0),
        classifier_(device_),
        trim_settings_(trim),
        group_(workgroup_size(device_, group_cap)),
        row_cap_(row_cap) {
    const std::uint32_t tile32 = tile_points(device_.limits(), 4);
    const std::uint32_t tile64 = tile_points(device_.limits(), 8);
    layout_tile32_ = tile_cap > 0 ? std::min(tile_cap, tile32) : tile32;
    layout_tile64_ = tile_cap > 0 ? std::min(tile_cap, tile64) : tile64;
    basis32_ = std::make_unique<vulkan::ComputePipeline>(
        device_, set_, sizeof(Launch), embedded::vk_compute_basis_f32_comp, "basis_f32.comp",
        std::vector<std::uint32_t>{group_, layout_tile32_});
    if (device_.float64()) {
      basis64_ = std::make_unique<vulkan::ComputePipeline>(
          device_, set_, sizeof(Launch), embedded::vk_compute_basis_f64_comp, "basis_f64.comp",
          std::vector<std::uint32_t>{group_, layout_tile64_});
    }
    record_ = device_.record();
    record_.details["vk_compute_workgroup"] = std::to_string(group_);
    record_.details["vk_compute_tile_points"] = fmt::format("{} (f32), {} (f64)", tile32, tile64);
    record_.details["shaderFloat64"] = device_.float64() ? "yes" : "no";
    if (tile_cap > 0) record_.details["vk_tile_points"] = std::to_string(tile_cap);
    trim_direct::record_settings(trim_settings_, record_);
  }

  std::string_view name() const override { return "vk-compute"; }
  Capabilities capabilities() const override { return vk_compute_descriptor().capabilities; }
  DeviceInfo device() const override { return record_; }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    if (request.precision == Precision::f64 && !device_.float64())
      throw RefusedError(
          fmt::format("vk-compute: f64 needs shaderFloat64, not supported by {}", record_.name));
    const vulkan::UploadCount uploads(device_, record_);
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    classified_ = false;
    if (request.precision == Precision::f32)
      upload(TableBuilder<float>(group_, layout_tile32_, row_cap_).build(scene, samples_));
    else
      upload(TableBuilder<double>(group_, layout_tile64_, row_cap_).build(scene, samples_));
    classifier_.prepare(scene, samples_, trim_settings_);
    eval_ = &eval_pipeline(request.precision == Precision::f64, scene);
  }

  void evaluate() override {
    const bool f64 = request_.precision == Precision::f64;
    const vulkan::ComputePipeline& basis = f64 ? *basis64_ : *basis32_;
    const vulkan::ComputePipeline& eval = *eval_;
    const auto& limits = device_.limits();
    const auto param_grid = grid_of((param_count_ + group_ - 1) / group_, limits);
    const auto tile_grid = grid_of(tile_count_, limits);
    device_.submit_and_wait([&](VkCommandBuffer cb) {
      queries_.reset(cb);
      queries_.begin(cb);
      Launch launch;
      launch.normals = request_.normals ? 1 : 0;
      launch.paired = paired_ ? 1 : 0;
      launch.params = static_cast<std::int32_t>(param_count_);
      if (param_count_ > 0) {
        basis.bind(cb, set_);
        launch.count = static_cast<std::int32_t>(param_count_);
        launch.tiles_x = static_cast<std::int32_t>(param_grid[0]);
        vkCmdPushConstants(cb, basis.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof launch,
                           &launch);
        vkCmdDispatch(cb, param_grid[0], param_grid[1], 1);
        memory_barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
      }
      if (tile_count_ > 0) {
        eval.bind(cb, set_);
        launch.count = static_cast<std::int32_t>(tile_count_);
        launch.tiles_x = static_cast<std::int32_t>(tile_grid[0]);
        vkCmdPushConstants(cb, eval.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof launch,
                           &launch);
        vkCmdDispatch(cb, tile_grid[0], tile_grid[1], 1);
      }
      queries_.end(cb);
      memory_barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
    });
    times_.evaluate_s = queries_.elapsed_s();
    evaluated_ = true;
  }

  bool classify() override {
    if (classifier_.trims())
      device_.submit_and_wait([&](VkCommandBuffer cb) { classifier_.record(cb); });
    classified_ = true;
    return true;
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  void read_back_into(EvalResult& out) override {
    if (request_.precision == Precision::f32)
      read_all<float>(out);
    else
      read_all<double>(out);
    if (classified_ && classifier_.trims()) {
      trim_direct::Cost cost;
      auto masks = classifier_.read_masks(cost);
      trim_direct::record_cost(cost, record_);
      for (std::size_t i = 0; i < out.surfaces.size(); ++i)
        out.surfaces[i].inside = std::move(masks[i]);
    }
  }

  // Knots, degrees and samples stay; only the homogeneous nets are sent again.
  void update_control_points(const Scene& scene) override {
    if (request_.precision == Precision::f32)
      update_nets<float>(scene);
    else
      update_nets<double>(scene);
  }

  DeviceTimes device_times() const override { return times_; }

 private:
  Buffer storage(const void* data, std::size_t bytes, const char* what) {
    // never empty: a descriptor needs a buffer, and a scene may have no parameter of some kind
    Buffer b(device_, std::max<std::size_t>(bytes, 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, what);
    if (data && bytes > 0) b.write(data, bytes);
    return b;
  }
  template <typename V>
  Buffer storage(const std::vector<V>& v, const char* what) {
    return storage(v.data(), v.size() * sizeof(V), what);
  }

  template <typename T>
  void upload(Tables<T>&& t) {
    const std::size_t total = total_samples(samples_);
    paired_ = !samples_.empty() && !samples_.front().tensor;
    param_count_ = static_cast<std::uint32_t>(t.params.size());
    tile_count_ = static_cast<std::uint32_t>(t.tiles.size() / TC_TILE_INTS);
    knots_ = storage(t.knots, "knots");
    params_ = storage(t.params, "parameters");
    param_axes_ = storage(t.param_axes, "parameter axes");
    spans_ = storage(nullptr, t.params.size() * sizeof(std::int32_t), "spans");
    basis_ = storage(nullptr, t.params.size() * TB_STRIDE * sizeof(T), "basis values");
    nets_ = storage(t.nets, "control nets");
    net_bytes_ = t.nets.size() * sizeof(T);
    surfaces_ = storage(t.surfaces, "surface table");
    tiles_ = storage(t.tiles, "tile table");
    positions_ = storage(nullptr, total * 3 * sizeof(T), "positions");
    normals_ = storage(nullptr, request_.normals ? total * 3 * sizeof(T) : 0, "normals");
    set_.write({&knots_, &params_, &param_axes_, &spans_, &basis_, &nets_, &surfaces_, &tiles_,
                &positions_, &normals_});
    if constexpr (std::is_same_v<T, float>)
      host_nets32_ = std::move(t.host_nets);
    else
      host_nets64_ = std::move(t.host_nets);
    evaluated_ = false;
  }

  template <typename T>
  void update_nets(const Scene& scene) {
    const std::vector<T> nets = homogeneous_nets<T>(scene);
    if (nets.size() * sizeof(T) != net_bytes_)
      throw std::invalid_argument("vk-compute: update_control_points changed the control nets");
    nets_.write(nets.data(), net_bytes_);
    auto& host = [this]() -> std::vector<SurfaceNet<T>>& {
      if constexpr (std::is_same_v<T, float>)
        return host_nets32_;
      else
        return host_nets64_;
    }();
    for (std::size_t i = 0; i < host.size(); ++i) host[i] = SurfaceNet<T>(scene.surfaces[i]);
  }

  // Straight from where the device left the results (the mapping on lavapipe, the device's
  // staging buffer on a GPU) into out's kept storage: one host copy of each byte.
  template <typename T>
  void read_all(EvalResult& out) {
    const std::size_t total = total_samples(samples_);
    const std::size_t bytes = total * 3 * sizeof(T);
    if (!evaluated_ || total == 0) {
      shape_results(out, samples_, request_.precision, request_.normals);
      return;
    }
    // One view at a time: the staging buffer holds one, so the positions are in place before the
    // normals are viewed.
    shape_results(out, samples_, request_.precision, request_.normals);
    scatter_into(out, &SurfaceResult::positions,
                 static_cast<const T*>(positions_.host_view(bytes)));
    if (!request_.normals) return;
    scatter_into(out, &SurfaceResult::normals, static_cast<const T*>(normals_.host_view(bytes)));
    std::size_t base = 0;
    const auto& host = [this]() -> const std::vector<SurfaceNet<T>>& {
      if constexpr (std::is_same_v<T, float>)
        return host_nets32_;
      else
        return host_nets64_;
    }();
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      SurfaceResult& r = out.surfaces[i];
      const SurfaceSamples& ss = samples_[i];
      const std::size_t n = ss.count();
      T* normal = r.normals.data<T>();
      // The device leaves the zero vector where neither Su x Sv nor the limit normal resolved
      // (eval.glsl): the reference's last stage, a nudged neighbour, here -- rare, and what
      // the reference itself returns where that fails too (a surface collapsed to a curve).
      for (std::size_t k = 0; k < n; ++k) {
        T* m = normal + 3 * k;
        if (m[0] != T(0) || m[1] != T(0) || m[2] != T(0)) continue;
        const Vec3<T> fixed =
            surface_normal(host[i], static_cast<T>(ss.u_of(k)), static_cast<T>(ss.v_of(k)));
        std::copy(fixed.begin(), fixed.end(), m);
      }
      base += n;
    }
  }

  // The scene's one degree pair as constants, or (0, 0) when its surfaces differ.
  const vulkan::ComputePipeline& eval_pipeline(bool f64, const Scene& scene) {
    int p = scene.surfaces.empty() ? 0 : scene.surfaces.front().degree_u;
    int q = scene.surfaces.empty() ? 0 : scene.surfaces.front().degree_v;
    for (const Surface& s : scene.surfaces)
      if (s.degree_u != p || s.degree_v != q) p = q = 0;
    auto& pipeline = eval_pipelines_[{f64, p, q}];
    if (!pipeline)
      pipeline = std::make_unique<vulkan::ComputePipeline>(
          device_, set_, sizeof(Launch),
          f64 ? embedded::vk_compute_eval_f64_comp : embedded::vk_compute_eval_f32_comp,
          f64 ? "eval_f64.comp" : "eval_f32.comp",
          std::vector<std::uint32_t>{group_, f64 ? layout_tile64_ : layout_tile32_,
                                     static_cast<std::uint32_t>(p), static_cast<std::uint32_t>(q)});
    record_.details["vk_compute_degrees"] =
        p > 0 ? fmt::format("{}x{} (constants)", p, q) : "per surface (mixed)";
    return *pipeline;
  }

  vulkan::Device device_;
  vulkan::StorageSet set_;
  vulkan::QueryPools queries_;
  vulkan::TrimClassifier classifier_;
  trim_direct::Settings trim_settings_;
  std::uint32_t group_, row_cap_;
  std::uint32_t layout_tile32_ = 0, layout_tile64_ = 0;  // curve points a tile may use
  std::unique_ptr<vulkan::ComputePipeline> basis32_, basis64_;
  // The evaluation pass per precision and degree pair (eval.glsl's kDegreeU, kDegreeV; 0, 0: the
  // degrees read from the table), made when a scene first needs it and kept for the next prepare.
  std::map<std::tuple<bool, int, int>, std::unique_ptr<vulkan::ComputePipeline>> eval_pipelines_;
  const vulkan::ComputePipeline* eval_ = nullptr;
  DeviceInfo record_;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  Buffer knots_, params_, param_axes_, spans_, basis_, nets_, surfaces_, tiles_, positions_,
      normals_;
  std::vector<SurfaceNet<float>> host_nets32_;
  std::vector<SurfaceNet<double>> host_nets64_;
  std::size_t net_bytes_ = 0;
  std::uint32_t param_count_ = 0, tile_count_ = 0;
  bool paired_ = false, classified_ = false, evaluated_ = false;
  DeviceTimes times_;  // the phases' last device times (device_times())
};

// The options' positive counts (absent: `otherwise`). extra["vk-tile-points"] = N (16 or more): at
// most N curve points per shared-memory tile, below what the device's shared memory holds (the
// tests use it to cut grids into many tiles); extra["vk-workgroup"] = N: N invocations per
// work-group instead of four subgroups (within the device's limits); extra["vk-tile-rows"] = N: at
// most N rows per tile instead of kMaxTileRows. The last two are for measuring the choices.
std::uint32_t count_option(const StrategyOptions& options, const char* key, int least,
                           std::uint32_t otherwise) {
  const auto it = options.extra.find(key);
  if (it == options.extra.end()) return otherwise;
  std::size_t used = 0;
  int n = 0;
  try {
    n = std::stoi(it->second, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != it->second.size() || n < least)
    throw std::invalid_argument(fmt::format("vk-compute option {} = '{}': must be an integer >= {}",
                                            key, it->second, least));
  return static_cast<std::uint32_t>(n);
}

std::unique_ptr<Strategy> make_vk_compute(const StrategyOptions& options) {
  try {
    return std::make_unique<VkCompute>(vulkan::device_option(options),
                                       trim_direct::settings_from(options, "vk-compute"),
                                       count_option(options, "vk-tile-points", TB_MAX_ORDER, 0),
                                       count_option(options, "vk-workgroup", 1, 0),
                                       count_option(options, "vk-tile-rows", 1, kMaxTileRows));
  } catch (const vulkan::MissingFeature& e) {
    throw std::runtime_error(std::string("unavailable: ") + e.what());
  }
}

}  // namespace

StrategyEntry vk_compute_entry() {
  return make_entry(
      vk_compute_descriptor(), [] { return vulkan::probe(compute_requirements()); },
      make_vk_compute);
}

namespace vk_compute {

namespace {
template <typename T>
std::vector<BasisRun> basis_run(const std::vector<BasisJob>& jobs, int device_index) {
  const vulkan::Device device(device_index, compute_requirements());
  if (std::is_same_v<T, double> && !device.float64())
    throw RefusedError("vk-compute: shaderFloat64 not supported");
  const vulkan::StorageSet set(
      device, std::vector<VkShaderStageFlags>(kBindings, VK_SHADER_STAGE_COMPUTE_BIT));
  const std::uint32_t group = workgroup_size(device, 0);
  const vulkan::ComputePipeline pipeline(device, set, sizeof(Launch),
                                         std::is_same_v<T, float>
                                             ? embedded::vk_compute_basis_f32_comp
                                             : embedded::vk_compute_basis_f64_comp,
                                         "basis.comp", {group, 64});
  // every job in one dispatch: knots one vector after the other, each parameter naming its own
  std::vector<T> knots, params;
  std::vector<std::int32_t> axes;
  for (const BasisJob& job : jobs) {
    const auto offset = static_cast<std::int32_t>(knots.size());
    const int count = static_cast<int>(job.knots.size()) - job.degree - 1;
    knots.insert(knots.end(), job.knots.begin(), job.knots.end());
    params.insert(params.end(), job.params.begin(), job.params.end());
    for (std::size_t k = 0; k < job.params.size(); ++k)
      axes.insert(axes.end(), {offset, job.degree, count});
  }
  const auto make = [&](const void* data, std::size_t bytes, const char* what) {
    Buffer b(device, std::max<std::size_t>(bytes, 16), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, what);
    if (data) b.write(data, bytes);
    return b;
  };
  const std::size_t n = params.size();
  Buffer kb = make(knots.data(), knots.size() * sizeof(T), "knots");
  Buffer pb = make(params.data(), n * sizeof(T), "parameters");
  Buffer ab = make(axes.data(), axes.size() * sizeof(std::int32_t), "axes");
  Buffer sb = make(nullptr, n * sizeof(std::int32_t), "spans");
  Buffer vb = make(nullptr, n * TB_STRIDE * sizeof(T), "values");
  Buffer unused = make(nullptr, 16, "unused");
  set.write({&kb, &pb, &ab, &sb, &vb, &unused, &unused, &unused, &unused, &unused});
  const auto grid = grid_of((static_cast<std::uint32_t>(n) + group - 1) / group, device.limits());
  Launch launch;
  launch.count = static_cast<std::int32_t>(n);
  launch.params = static_cast<std::int32_t>(n);
  launch.normals = 1;
  launch.tiles_x = static_cast<std::int32_t>(grid[0]);
  device.submit_and_wait([&](VkCommandBuffer cb) {
    pipeline.bind(cb, set);
    vkCmdPushConstants(cb, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof launch,
                       &launch);
    vkCmdDispatch(cb, grid[0], grid[1], 1);
  });
  std::vector<std::int32_t> spans(n);
  sb.read(spans.data(), n * sizeof(std::int32_t));
  std::vector<T> values(n * TB_STRIDE);
  vb.read(values.data(), values.size() * sizeof(T));
  std::vector<BasisRun> runs;
  std::size_t g = 0;
  for (const BasisJob& job : jobs) {
    BasisRun& run = runs.emplace_back();
    for (std::size_t k = 0; k < job.params.size(); ++k, ++g) {
      run.spans.push_back(spans[g]);
      for (int j = 0; j < TB_STRIDE; ++j) run.values.push_back(values[j * n + g]);
    }
  }
  return runs;
}
}  // namespace

std::vector<BasisRun> basis_on_vulkan(const std::vector<BasisJob>& jobs, bool f64,
                                      int device_index) {
  return f64 ? basis_run<double>(jobs, device_index) : basis_run<float>(jobs, device_index);
}

}  // namespace vk_compute
}  // namespace nurbs
