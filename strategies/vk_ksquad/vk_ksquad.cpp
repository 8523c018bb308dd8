// vk-ksquad (003 §2-4). Where the paper is ambiguous or D3D11-specific, and what we chose:
//  * D3D11 hull / domain shaders -> Vulkan tessellation control / evaluation shaders; the
//    paper's vertex buffer of KSQuad ids -> no vertex input at all: one vertex per patch and
//    gl_PrimitiveID as the row of the Info-KSQuad table (003 Fig 8's first level of indirection;
//    the surface table is the second).
//  * "Per-KSQuad constant denominators computed once" (§3.2): computed once per non-empty span
//    and direction on the host by the tested C++ stair_constants<float> (the same float
//    arithmetic the device would do, correctly rounded divisions) and read from a storage buffer;
//    KSQuads sharing a span share its constants.
//  * Uniform mode (003 §4's uniform mapping): the levels of a patch are the segment counts of its
//    u and v runs. Span grid T: the tessellator chooses the samples -- its (T+1)x(T+1) lattice
//    per KSQuad (DESIGN.md's span grid), the parameter blended from the span's knots by
//    gl_TessCoord (ksquad.tese span_parameter) and returned with the position, so the samples
//    are the float rounding of the requested ones. Grid (the paper has no grids; our mapping):
//    gl_TessCoord indexes the KSQuad's sub-grid of requested samples, evaluated at exactly the
//    requested parameters; render() instead draws every patch over its span share from the
//    knots (patches share their boundary vertices on the knot lines; every non-empty span pair
//    is a patch, samples or not). Runs past maxTessellationGenerationLevel are cut into several
//    patches (patches.h), never clamped.
//  * Capture: storage-buffer writes from the evaluation stage (vertexPipelineStoresAndAtomics),
//    rasterization discarded; transform feedback would need a vertex order the tessellator does
//    not specify.
//  * Adaptive mode (003 §3.1, local area average): the KSQuad corners S(x_k, y_l), one table
//    shared by the KSQuads meeting there, evaluated on the device by a compute pass before the
//    draws of every evaluate()/render() (vk-corners=device, the default: 003 §1's "whole NURBS
//    equation in the GPU without any precomputation on the CPU"; each corner once, with the span
//    A2.1 assigns it, so neighbours read the same float) or on the host by the reference in
//    double (vk-corners=host, kept to measure the difference); the control stage projects an
//    edge's two corners with the camera and sets that edge's level alone from them (ksquad.tesc). A
//    level past the cap (vk-max-level, at most maxTessellationGenerationLevel) is cut, not capped:
//    each KSQuad is vk-pieces^2 rows of the Info-KSQuad table and the control stage uses as many as
//    its levels need, each outer edge cut on its own so the KSQuad across it cuts at the same
//    vertices (the host cannot cut: it does not know the levels). Past vk-pieces x the cap a level
//    is capped and counted (KsquadStatistics::capped_edges).
//  * GS mode (003 §4's first mapping, vk-mode=gs): no tessellator; the geometry stage evaluates
//    or emits each KSQuad's span-grid lattice (ksquad.geom), T <= 8 by its output limit.
//  * Nonuniform mode (003 §4's third mapping, vk-mode=nonuniform): adaptive mode's corners and
//    eq. 3 at vk-mu x 2^kNuDepth (the control stage's lower level, one regular lattice per
//    KSQuad), then the geometry stage's eq. 4 / eq. 5 subdivision and EVS culling per KSDie
//    (ksquad_nonuniform.geom), the friend surfaces found once in prepare (nonuniform_mapping.h).
#include "strategies/vk_ksquad/vk_ksquad.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "reference/nurbs_math.h"
#include "strategies/ksquad/ksquad_table.h"
#include "strategies/stair_basis/stair.h"
#include "strategies/strategy_options.h"
#include "strategies/trim_direct/trim_tables.h"
#include "strategies/vk_ksquad/adaptive_mapping.h"
#include "strategies/vk_ksquad/ksquad_layout.h"
#include "strategies/vk_ksquad/ksquad_pipeline.h"
#include "strategies/vk_ksquad/ksquad_settings.h"
#include "strategies/vk_ksquad/nonuniform_mapping.h"
#include "strategies/vk_ksquad/patches.h"
#include "strategies/vk_ksquad/uniform_mapping.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"
#include "strategies/vulkan/vk_device.h"
#include "strategies/vulkan/vk_trim_classify.h"

namespace nurbs::embedded {
extern const std::string_view vk_ksquad_corners_comp;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

using vk_ksquad::Draw;
using vk_ksquad::kCornerInts;
using vk_ksquad::kNuDepth;
using vk_ksquad::kNuKsdieInts;
using vk_ksquad::kNuLattice;
using vk_ksquad::kNuVertexFloats;
using vk_ksquad::kPatchInts;
using vk_ksquad::kPatchLevelU;
using vk_ksquad::kPatchLevelV;
using vk_ksquad::kSlotFloats;
using vk_ksquad::ksquad_settings;
using vk_ksquad::KsquadSettings;
using vk_ksquad::kSurfaceInts;
using vk_ksquad::ModeConstants;
using vulkan::memory_barrier;

constexpr int kConstantFloats = kStairConstantReals;
static_assert(sizeof(StairConstants<float>) == kConstantFloats * sizeof(float),
              "stair_basis.h reads StairConstants<float> as packed floats");
constexpr int kBuffers = 15;
// Bindings 9..11 are the fragment stage's trim test (ksquad.frag): the classifier's tables and
// one row of kTrimSurfaceInts per surface; 12 is the span grid's sample parameters; 14 the
// nonuniform mapping's KSDie records (ksquad_nonuniform.glsl).
constexpr int kFirstTrimBinding = 9, kTrimBindings = 3;
constexpr int kTrimSurfaceInts = 5;

// The stages that read the tables and the push constants; the GS mapping (ksquad.geom) adds its
// stage only where the geometry-shader feature is enabled (VkKsquad::draw_stages), the corner pass
// (ksquad_corners.comp) reads the same set through its own layout.
constexpr VkShaderStageFlags kModeStages =
    VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT;
constexpr std::uint32_t kCornerGroup = 64;  // ksquad_corners.comp: local_size_x
// ksquad.geom: max_vertices, the strips of span grid T = kGsMaxSteps (T strips of 2 (T + 1))
constexpr std::uint32_t kGsMaxVertices = 144;
constexpr int kGsMaxSteps = 8;
static_assert(kGsMaxSteps * 2 * (kGsMaxSteps + 1) == kGsMaxVertices);
// ksquad_nonuniform.geom: max_vertices, 2^kNuDepth strips of 2 (2^kNuDepth + 1)
constexpr std::uint32_t kNuMaxVertices = (1u << kNuDepth) * 2 * ((1u << kNuDepth) + 1);
static_assert(kNuMaxVertices == 40);
constexpr VkQueryPipelineStatisticFlags kStatistics =
    VK_QUERY_PIPELINE_STATISTIC_TESSELLATION_CONTROL_SHADER_PATCHES_BIT |
    VK_QUERY_PIPELINE_STATISTIC_TESSELLATION_EVALUATION_SHADER_INVOCATIONS_BIT;

vulkan::Requirements ksquad_requirements(bool geometry = false) {
  vulkan::Requirements r;
  r.geometry_shader = geometry;
  r.tessellation_shader = true;
  r.vertex_pipeline_stores = true;
  r.pipeline_statistics = true;
  return r;
}

Capabilities ksquad_capabilities() {
  Capabilities c;
  // 15, the validation limit: no device limit depends on the degree (net and constants are
  // storage buffers, one control point per patch; push constants and levels do not grow with it).
  c.max_degree = kStairMaxDegree;
  c.normals = true;  // both modes: derivatives of the same stair basis (stair_derivative)
  c.fp64 = false;    // Vulkan tessellation stages in float; shaderFloat64 is optional
  c.sampling.explicit_list = false;  // not a tensor of runs
  // The tessellator chooses the samples in adaptive mode and for span grids (the float rounding
  // of the requested ones); a grid's are the requested ones.
  c.chooses_own_samples = true;
  c.updates_control_points = true;  // re-uploads only the control points (and corners)
  // Uniform mode: direct trimming of the requested samples in a compute pass (the shared
  // vulkan::TrimClassifier); render() discards outside fragments with the same GLSL.
  c.trims = true;
  return c;
}

class VkKsquad final : public Strategy {
 public:
  VkKsquad(int device_index, const KsquadSettings& settings, const trim_direct::Settings& trim)
      : device_(device_index, ksquad_requirements(settings.gs || settings.nonuniform)),
        queries_(device_, kStatistics),
        classifier_(device_),
        trim_settings_(trim),
        settings_(settings) {
    record_ = device_.record();
    trim_direct::record_settings(trim_settings_, record_);
    const int cap = static_cast<int>(device_.limits().maxTessellationGenerationLevel);
    if (settings_.max_level == 0) settings_.max_level = cap;
    if (settings_.max_level > cap)
      throw std::invalid_argument(
          fmt::format("vk-ksquad: vk-max-level {} exceeds maxTessellationGenerationLevel {}",
                      settings_.max_level, cap));
    const VkPhysicalDeviceLimits& limits = device_.limits();
    if (settings_.gs && (limits.maxGeometryOutputVertices < kGsMaxVertices ||
                         limits.maxGeometryTotalOutputComponents < kGsMaxVertices * 7))
      throw vulkan::MissingFeature(
          fmt::format("vk-mode=gs needs {} geometry output vertices of 7 components (ksquad.geom)",
                      kGsMaxVertices));
    if (settings_.nonuniform && (limits.maxGeometryOutputVertices < kNuMaxVertices ||
                                 limits.maxGeometryTotalOutputComponents < kNuMaxVertices * 7))
      throw vulkan::MissingFeature(
          fmt::format("vk-mode=nonuniform needs {} geometry output vertices of 7 components "
                      "(ksquad_nonuniform.geom)",
                      kNuMaxVertices));
    // the report labels vk-ksquad's series by the mapping
    record_.details["vk_mode"] = settings_.gs ? "gs" : "uniform";
    if (settings_.adaptive) {
      record_.details["vk_mode"] = settings_.nonuniform ? "nonuniform" : "adaptive";
      record_.details["vk_corners"] = settings_.device_corners ? "device" : "host";
    }
    if (settings_.nonuniform) {
      record_.details["vk_epsilon"] = fmt::format("{}", settings_.epsilon);
      record_.details["vk_eta"] = fmt::format("{}", settings_.eta);
      record_.details["vk_max_level"] = std::to_string(settings_.max_level);
    }
    create_pipeline();
  }
  ~VkKsquad() override {
    vkDeviceWaitIdle(device_.handle());
    const VkDevice d = device_.handle();
    for (const auto& pipelines : {capture_pipelines_, raster_pipelines_})
      for (const auto& [degrees, pipeline] : pipelines) vkDestroyPipeline(d, pipeline, nullptr);
    if (layout_) vkDestroyPipelineLayout(d, layout_, nullptr);
  }

  std::string_view name() const override { return "vk-ksquad"; }
  Capabilities capabilities() const override { return ksquad_capabilities(); }
  DeviceInfo device() const override { return record_; }

  void prepare(const Scene& scene, const EvalRequest& request) override {
    refuse_unsupported(name(), capabilities(), scene, request);
    if (settings_.gs && (request.sampling.mode != SamplingMode::span_grid ||
                         request.sampling.span_steps > kGsMaxSteps))
      throw RefusedError(fmt::format(
          "vk-ksquad vk-mode=gs: span grids of at most {} steps only (a KSQuad's KSDice must fit "
          "one geometry-shader invocation's output, 003 §4)",
          kGsMaxSteps));
    const bool trimmed = std::any_of(scene.surfaces.begin(), scene.surfaces.end(),
                                     [](const Surface& s) { return s.trim.has_value(); });
    if (settings_.adaptive && trimmed)
      throw RefusedError(
          "vk-ksquad: trimmed scenes are classified in uniform mode only (adaptive samples are "
          "the tessellator's, known only after evaluate())");
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    build_tables(scene);
    classified_ = false;
    classifying_chosen_samples_ = false;
    classifier_.prepare(scene, samples_, trim_settings_);
    trim_surfaces_buf_ = storage(trim_surface_rows(), "trim surface table");
    upload_tables(scene);
    for (const Draw& draw : draws_) pipeline_for(capture_pipelines_, false, draw);
  }

  // Direct trimming (uniform mode): one compute dispatch per trimmed surface; the masks stay on
  // the device until read_back(). On a span grid the samples are the tessellator's (16.16 fixed
  // point: up to ~T/2 * 2^-17 of a span off the requested lattice), and those are what the
  // positions and the scoring use, so they are what is classified: read once after the first
  // evaluate() of a prepare (the tessellator is deterministic), sample by sample where they are
  // no longer a tensor grid.
  bool classify() override {
    if (classifier_.trims() && span_grid_samples() && !classifying_chosen_samples_) {
      std::vector<float> uv(total_ * 2);
      sample_params_.read(uv.data(), uv.size() * sizeof(float));
      std::vector<SurfaceSamples> chosen;
      std::size_t base = 0;
      for (const SurfaceSamples& s : samples_) {
        chosen.push_back(vk_ksquad::chosen_samples(s, uv.data() + 2 * base));
        base += s.count();
      }
      classifier_.set_samples(chosen);
      classifying_chosen_samples_ = true;
    }
    if (classifier_.trims())
      device_.submit_and_wait([&](VkCommandBuffer cb) { classifier_.record(cb); });
    classified_ = true;
    return true;
  }

  void evaluate() override {
    device_.submit_and_wait([&](VkCommandBuffer cb) {
      if (settings_.adaptive) {
        // Unwritten capture slots read back as NaN (a quiet NaN's bits in every word); nonuniform:
        // KSDice the tessellator did not start keep status 0.
        vkCmdFillBuffer(cb, positions_.handle(), 0, VK_WHOLE_SIZE, 0x7fc00000u);
        if (settings_.nonuniform) vkCmdFillBuffer(cb, ksdice_.handle(), 0, VK_WHOLE_SIZE, 0u);
        memory_barrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       writing_stages(), VK_ACCESS_SHADER_WRITE_BIT);
      }
      queries_.reset(cb);
      queries_.begin(cb);
      record_corners(cb);
      capture_->begin(cb);
      record_draws(cb, capture_pipelines_, draws_);
      vkCmdEndRenderPass(cb);
      queries_.end(cb);
      memory_barrier(cb, writing_stages(), VK_ACCESS_SHADER_WRITE_BIT,
                     VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
    });
    evaluate_s_ = queries_.elapsed_s();
    const auto counts = queries_.statistics();
    stats_.control_patches = counts.size() > 0 ? counts[0] : 0;
    stats_.evaluation_invocations = counts.size() > 1 ? counts[1] : 0;
  }

  EvalResult read_back() override {
    if (settings_.nonuniform) return read_back_nonuniform();
    if (settings_.adaptive) return read_back_adaptive();
    EvalResult out{vk_ksquad::read_uniform_capture(samples_, positions_,
                                                   span_grid_samples() ? &sample_params_ : nullptr,
                                                   request_.normals ? &normals_ : nullptr)};
    if (classified_ && classifier_.trims()) {
      trim_direct::Cost cost;
      auto masks = classifier_.read_masks(cost);
      trim_direct::record_cost(cost, record_);
      for (std::size_t i = 0; i < out.surfaces.size(); ++i)
        out.surfaces[i].inside = std::move(masks[i]);
    }
    return out;
  }

  // Only the homogeneous control points change (same knots, degrees and samples): the tables
  // and constants stay.
  void update_control_points(const Scene& scene) override {
    const std::vector<float> points = homogeneous_points(scene);
    if (points.size() * sizeof(float) != points_.size())
      throw std::invalid_argument("vk-ksquad: update_control_points changed the control nets");
    points_.write(points.data(), points.size() * sizeof(float));
    if (settings_.adaptive && !settings_.device_corners) {  // the corners move with the points
      corners_ = vk_ksquad::corner_table(scene, true).rows;
      corners_buf_.write(corners_.data(), corners_.size() * sizeof(float));
    }
  }

  DeviceTimes device_times() const override { return {evaluate_s_}; }

  // 003 §4 end to end: the same patches drawn with rasterization into an offscreen image (the
  // camera of the adaptive settings; fitted to the scene by default), positions never stored.
  // Returns when the device is done; the runner times it as the `render` phase.
  bool render() override {
    if (!raster_)
      raster_ = std::make_unique<vk_ksquad::RasterTarget>(device_, image_width(), image_height());
    for (const Draw& draw : raster_draws_) pipeline_for(raster_pipelines_, true, draw);
    device_.submit_and_wait([&](VkCommandBuffer cb) {
      VkClearValue clear[2] = {};
      clear[0].color = {{0.0f, 0.0f, 0.0f, 0.0f}};
      clear[1].depthStencil = {1.0f, 0};
      VkRenderPassBeginInfo begin{};
      begin.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
      begin.renderPass = raster_->pass();
      begin.framebuffer = raster_->framebuffer();
      begin.renderArea.extent = {image_width(), image_height()};
      begin.clearValueCount = 2;
      begin.pClearValues = clear;
      record_corners(cb);
      vkCmdBeginRenderPass(cb, &begin, VK_SUBPASS_CONTENTS_INLINE);
      record_draws(cb, raster_pipelines_, raster_draws_);
      vkCmdEndRenderPass(cb);
    });
    return true;
  }

  // Tests: pixels of the last render() that are not the clear colour.
  std::size_t rendered_pixels() const {
    const std::optional<RenderedImage> image = read_image();
    if (!image) return 0;
    std::size_t covered = 0;
    for (std::size_t p = 0; p < image->rgba.size(); p += 4)
      covered += image->rgba[p] != 0 || image->rgba[p + 1] != 0 || image->rgba[p + 2] != 0 ||
                 image->rgba[p + 3] != 0;
    return covered;
  }

  std::optional<RenderedImage> last_render() override { return read_image(); }
  std::optional<RenderedImage> read_image() const {
    if (!raster_) return std::nullopt;
    return raster_->read();
  }

  // Adaptive mode: the levels the control stage chose, read back from its storage buffer.
  KsquadStatistics statistics() const {
    if (!settings_.adaptive || patch_count_ == 0) return stats_;
    const KsquadStatistics st = vk_ksquad::adaptive_statistics(
        stats_, tables_, read_levels(), settings_.max_level * settings_.pieces);
    return settings_.nonuniform ? vk_ksquad::nonuniform_statistics(st, ksdice()) : st;
  }

  std::vector<KsdieRecord> ksdice() const {
    if (!settings_.nonuniform || patch_count_ == 0) return {};
    std::vector<int> records(patch_count_ * vk_ksquad::ksdie_slots(settings_.max_level) *
                             kNuKsdieInts);
    ksdice_.read(records.data(), records.size() * sizeof(int));
    return vk_ksquad::nonuniform_records(tables_, read_levels(), records, settings_.max_level);
  }

  std::vector<float> read_levels() const {
    std::vector<float> levels(8 * patch_count_);
    levels_.read(levels.data(), levels.size() * sizeof(float));
    return levels;
  }

  std::vector<PatchLevels> patch_levels() const {
    if (!settings_.adaptive || patch_count_ == 0) return {};
    return vk_ksquad::adaptive_patch_levels(tables_, read_levels());
  }

  std::vector<CapturedEdge> captured_edges() const {
    if (!settings_.adaptive || settings_.nonuniform) return {};
    return vk_ksquad::adaptive_edges(tables_, read_slots(), region_, settings_.max_level);
  }

 private:
  // Uniform span grid: the tessellator chooses the parameters (ksquad.tese span_parameter).
  bool span_grid_samples() const {
    return !settings_.adaptive && request_.sampling.mode == SamplingMode::span_grid;
  }

  static std::vector<float> homogeneous_points(const Scene& scene) {
    std::vector<float> points;
    for (const Surface& s : scene.surfaces) {
      const SurfaceNet<float> net(s);
      for (const Vec4<float>& h : net.homogeneous) points.insert(points.end(), h.begin(), h.end());
    }
    return points;
  }

  // ksquad.frag's per-surface trim row: tables base (-1: untrimmed), the local frame's origin and
  // ε as float bits, the iteration limit.
  std::vector<std::int32_t> trim_surface_rows() const {
    std::vector<std::int32_t> rows;
    for (const auto& st : classifier_.tables().surfaces)
      rows.insert(rows.end(),
                  {st.base, std::bit_cast<std::int32_t>(static_cast<float>(st.origin_u)),
                   std::bit_cast<std::int32_t>(static_cast<float>(st.origin_v)),
                   std::bit_cast<std::int32_t>(st.epsilon), trim_settings_.iterations});
    static_assert(kTrimSurfaceInts == 5);
    return rows;
  }

  std::vector<float> read_slots() const {
    std::vector<float> slots(patch_count_ * region_ * kSlotFloats);
    positions_.read(slots.data(), slots.size() * sizeof(float));
    return slots;
  }

  // The geometry stage's emitted vertices; its counters go into the record's details (the runner
  // reads device() after read_back()).
  EvalResult read_back_nonuniform() {
    const KsquadStatistics st = statistics();
    record_.details["nu_ksdice"] = std::to_string(st.ksdice);
    record_.details["nu_subdivided_linear"] = std::to_string(st.subdivided_linear);
    record_.details["nu_subdivided_boundary"] = std::to_string(st.subdivided_boundary);
    record_.details["nu_culled_frustum"] = std::to_string(st.culled_frustum);
    record_.details["nu_culled_back"] = std::to_string(st.culled_back);
    record_.details["nu_triangles"] = std::to_string(st.triangles);
    record_.details["nu_capped_edges"] = std::to_string(st.capped_edges);
    std::vector<float> slots(patch_count_ * vk_ksquad::ksdie_slots(settings_.max_level) *
                             kNuLattice * kNuLattice * kNuVertexFloats);
    positions_.read(slots.data(), slots.size() * sizeof(float));
    return vk_ksquad::nonuniform_result(tables_, slots, request_.normals, settings_.max_level,
                                        surface_count_);
  }

  EvalResult read_back_adaptive() {
    std::vector<float> slot_normals(request_.normals ? patch_count_ * region_ * 3 : 0);
    if (!slot_normals.empty())
      normals_.read(slot_normals.data(), slot_normals.size() * sizeof(float));
    return vk_ksquad::adaptive_result(tables_, read_slots(), slot_normals, region_, surface_count_);
  }

  // The adaptive camera: given, or fitted to the scene's control-point bounding sphere.
  void set_mode(const Scene& scene) {
    mode_ = {};
    mode_.adaptive = settings_.adaptive ? 1 : 0;
    mode_.max_level = settings_.max_level;
    mode_.pieces = settings_.pieces;
    mode_.region = static_cast<std::int32_t>(region_);
    mode_.normals = request_.normals ? 1 : 0;
    mode_.span_grid = span_grid_samples() ? 1 : 0;
    // nonuniform: the control stage's lower level (ksquad.tesc)
    mode_.mu =
        static_cast<float>(settings_.nonuniform ? settings_.mu * (1 << kNuDepth) : settings_.mu);
    mode_.nonuniform = settings_.nonuniform ? 1 : 0;
    mode_.epsilon = static_cast<float>(settings_.epsilon);
    mode_.eta = static_cast<float>(settings_.eta);
    mode_.viewport[0] = static_cast<float>(settings_.viewport[0]);
    mode_.viewport[1] = static_cast<float>(settings_.viewport[1]);
    const auto m = vk_ksquad::scene_camera(scene, settings_);
    std::copy(m.begin(), m.end(), mode_.view_projection);
  }

  // Surface table, per-span stair constants and the Info-KSQuad table (one row per patch).
  void build_tables(const Scene& scene) {
    vk_ksquad::SurfaceTable table = vk_ksquad::surface_table(scene, samples_);
    tables_.surfaces = std::move(table.surfaces);
    if (settings_.nonuniform) {
      const std::vector<int> friendless = vk_ksquad::friendless_sides(scene);
      for (std::size_t i = 0; i < friendless.size(); ++i)
        tables_.surfaces[i * kSurfaceInts + vk_ksquad::kSurfaceFriendless] = friendless[i];
    }
    tables_.patches.clear();
    tables_.constants.clear();
    params_ = std::move(table.params);
    total_ = table.total;
    // (surface, direction, span) -> offset of its constants in floats.
    std::map<std::tuple<int, int, int>, int> constant_of;
    const auto constants = [&](int surface, int direction, int span) {
      const auto key = std::make_tuple(surface, direction, span);
      if (auto it = constant_of.find(key); it != constant_of.end()) return it->second;
      const Surface& s = scene.surfaces[surface];
      const std::vector<double>& k64 = direction == 0 ? s.knots_u : s.knots_v;
      const std::vector<float> k32(k64.begin(), k64.end());
      StairConstants<float> c{};
      stair_constants(span, direction == 0 ? s.degree_u : s.degree_v, k32.data(), c);
      const int offset = static_cast<int>(tables_.constants.size());
      const float* f = reinterpret_cast<const float*>(&c);
      tables_.constants.insert(tables_.constants.end(), f, f + kConstantFloats);
      constant_of.emplace(key, offset);
      return offset;
    };
    const int cap = static_cast<int>(device_.limits().maxTessellationGenerationLevel);
    stats_ = {};
    stats_.level_cap = settings_.adaptive ? settings_.max_level : cap;
    surface_count_ = scene.surfaces.size();
    // Adaptive: one patch per KSQuad of the span grid (the tessellator chooses the samples).
    Sampling one_per_span;
    one_per_span.mode = SamplingMode::span_grid;
    one_per_span.span_steps = 1;
    const auto quads = settings_.adaptive
                           ? ksquad::build_ksquads<float>(
                                 scene, sample_parameters(scene, one_per_span), one_per_span)
                           : (span_grid_samples()
                                  ? ksquad::build_ksquads<float>(scene, samples_, request_.sampling)
                                  : vk_ksquad::grid_ksquads(scene, samples_));
    corner_table_ = settings_.adaptive ? vk_ksquad::corner_table(scene, !settings_.device_corners)
                                       : vk_ksquad::Corners{};
    corners_ = corner_table_.rows;
    corner_jobs_.clear();
    if (settings_.adaptive && settings_.device_corners)
      for (const auto& [surface, span_u, span_v, end_u, end_v] : corner_table_.spans)
        corner_jobs_.insert(corner_jobs_.end(),
                            {surface * kSurfaceInts, span_u, span_v, constants(surface, 0, span_u),
                             constants(surface, 1, span_v), end_u, end_v, 0});
    for (const ksquad::KSQuad& q : quads) {
      const Surface& s = scene.surfaces[q.surface];
      const int cu = constants(q.surface, 0, q.u.span), cv = constants(q.surface, 1, q.v.span);
      int c[4] = {0, 0, 0, 0};
      if (settings_.adaptive)
        for (int k = 0; k < 4; ++k)
          c[k] = corner_table_.at(s, q.surface, q.u.span + (k & 1), q.v.span + (k >> 1));
      // A2.1 puts a span's end knot in the next non-empty span (the last span keeps the end).
      const auto next_span = [](const std::vector<double>& k, int span, int count) {
        for (int t = span + 1; t < count; ++t)
          if (k[t] < k[t + 1]) return t;
        return span;
      };
      const int next_u = next_span(s.knots_u, q.u.span, s.count_u);
      const int next_v = next_span(s.knots_v, q.v.span, s.count_v);
      const int cu_next = constants(q.surface, 0, next_u);
      const int cv_next = constants(q.surface, 1, next_v);
      // Uniform: runs past the cap cut on the host; adaptive: vk-pieces^2 rows per KSQuad, the
      // control stage uses those its levels need (ksquad.tesc).
      const int piece_cap = settings_.adaptive ? std::numeric_limits<int>::max() : cap;
      const int pieces = settings_.adaptive ? settings_.pieces * settings_.pieces : 1;
      for (const ksquad::SpanRun& a : vk_ksquad::split_run(q.u, piece_cap))
        for (const ksquad::SpanRun& b : vk_ksquad::split_run(q.v, piece_cap))
          for (int piece = 0; piece < pieces; ++piece) {
            const int lu = vk_ksquad::run_level(a), lv = vk_ksquad::run_level(b);
            const auto [u_lo, u_hi] = vk_ksquad::piece_share(q.u, a);
            const auto [v_lo, v_hi] = vk_ksquad::piece_share(q.v, b);
            const int row[kPatchInts] = {q.surface,
                                         q.u.span,
                                         q.v.span,
                                         cu,
                                         cv,
                                         a.begin,
                                         a.count,
                                         b.begin,
                                         b.count,
                                         lu,
                                         lv,
                                         piece,
                                         c[0],
                                         c[1],
                                         c[2],
                                         c[3],
                                         next_u,
                                         next_v,
                                         cu_next,
                                         cv_next,
                                         std::bit_cast<int>(u_lo),
                                         std::bit_cast<int>(u_hi),
                                         std::bit_cast<int>(v_lo),
                                         std::bit_cast<int>(v_hi)};
            tables_.patches.insert(tables_.patches.end(), row, row + kPatchInts);
            stats_.implied_vertices += vk_ksquad::quad_domain_vertices(lu, lv);
            stats_.max_level = std::max({stats_.max_level, lu, lv});
          }
    }
    vk_ksquad::sort_by_degrees(tables_.patches, scene);
    // Adaptive patches are counted at the level cap (the control stage sets their levels).
    const std::uint64_t fixed_vertices =
        settings_.adaptive
            ? vk_ksquad::quad_domain_vertices(settings_.max_level, settings_.max_level)
            : 0;
    const auto make_draws = [&](bool with_empty) {
      return vk_ksquad::make_draws(tables_.patches, scene, with_empty, settings_.vertices_per_draw,
                                   fixed_vertices);
    };
    draws_ = make_draws(false);
    raster_draws_ = make_draws(true);
    record_.details["draws"] = std::to_string(draws_.size());
    patch_count_ = tables_.patch_count();
    stats_.patches_drawn = 0;
    for (const Draw& draw : draws_) stats_.patches_drawn += draw.count;
  }

  template <typename V>
  vulkan::Buffer storage(const std::vector<V>& data, const char* what) {
    vulkan::Buffer b(device_, data.size() * sizeof(V), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, what);
    b.write(data.data(), data.size() * sizeof(V));
    return b;
  }

  void upload_tables(const Scene& scene) {
    const int level = settings_.max_level;
    region_ = settings_.adaptive
                  ? static_cast<std::size_t>(4 * (level + 1) + (level - 1) * (level - 1))
                  : 0;
    set_mode(scene);
    const std::size_t ksdie_slots =
        settings_.nonuniform ? patch_count_ * vk_ksquad::ksdie_slots(settings_.max_level) : 0;
    const std::size_t output_floats =
        settings_.nonuniform
            ? ksdie_slots * kNuLattice * kNuLattice * kNuVertexFloats
            : (settings_.adaptive ? patch_count_ * region_ * kSlotFloats : total_ * 3);
    ksdice_ = vulkan::Buffer(device_, ksdie_slots * kNuKsdieInts * sizeof(int),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "KSDie records");
    corners_buf_ = storage(corners_, "KSQuad corners");
    corner_jobs_buf_ = storage(corner_jobs_, "KSQuad corner jobs");
    levels_ = vulkan::Buffer(device_, 8 * patch_count_ * sizeof(float),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "chosen levels");
    surfaces_buf_ = storage(tables_.surfaces, "surface table");
    patches_buf_ = storage(tables_.patches, "Info-KSQuad table");
    constants_buf_ = storage(tables_.constants, "stair constants");
    points_ = storage(homogeneous_points(scene), "control points");
    params_buf_ = storage(params_, "parameters");
    positions_ = vulkan::Buffer(device_, output_floats * sizeof(float),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output positions");
    // nonuniform: the normals are in the vertex slots
    const std::size_t normal_slots =
        settings_.nonuniform ? 0 : (settings_.adaptive ? patch_count_ * region_ : total_);
    normals_ = vulkan::Buffer(device_, (request_.normals ? normal_slots * 3 : 0) * sizeof(float),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output normals");
    sample_params_ = vulkan::Buffer(device_, (span_grid_samples() ? total_ * 2 : 0) * sizeof(float),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output sample parameters");
    set_->write({&surfaces_buf_, &patches_buf_, &constants_buf_, &points_, &params_buf_,
                 &positions_, &corners_buf_, &levels_, &normals_, &classifier_.reals(),
                 &classifier_.ints(), &trim_surfaces_buf_, &sample_params_, &corner_jobs_buf_,
                 &ksdice_});
  }

  // Once per strategy (STYLE.md: compiled shaders are created once, never in evaluate()).
  void create_pipeline() {
    std::vector<VkShaderStageFlags> stages(kBuffers, draw_stages() | VK_SHADER_STAGE_COMPUTE_BIT);
    for (int k = kFirstTrimBinding; k < kFirstTrimBinding + kTrimBindings; ++k)
      stages[k] = VK_SHADER_STAGE_FRAGMENT_BIT;
    set_ = std::make_unique<vulkan::StorageSet>(device_, stages);
    layout_ = vk_ksquad::make_layout(device_, *set_, draw_stages());
    corner_pass_ = std::make_unique<vulkan::ComputePipeline>(
        device_, *set_, static_cast<std::uint32_t>(sizeof(ModeConstants)),
        embedded::vk_ksquad_corners_comp, "ksquad_corners.comp");

    capture_ = std::make_unique<vk_ksquad::CaptureTarget>(device_);
  }

  using Pipelines = vk_ksquad::Pipelines;

  VkPipeline pipeline_for(Pipelines& pipelines, bool raster, const Draw& draw) {
    auto& pipeline = pipelines[{draw.du, draw.dv}];
    if (!pipeline)
      pipeline = vk_ksquad::make_pipeline(
          device_, vk_ksquad::ksquad_shaders(settings_.nonuniform), layout_, raster,
          settings_.gs ? vk_ksquad::Stages::geometry
                       : (settings_.nonuniform ? vk_ksquad::Stages::tessellation_geometry
                                               : vk_ksquad::Stages::tessellation),
          raster ? raster_->pass() : capture_->pass(), draw.du, draw.dv, image_width(),
          image_height());
    return pipeline;
  }

  // vk-corners=device: the corner pass, then a barrier so the control stage reads its corners.
  void record_corners(VkCommandBuffer cb) const {
    if (!settings_.adaptive || !settings_.device_corners || corner_jobs_.empty()) return;
    const auto count = static_cast<std::uint32_t>(corner_jobs_.size() / kCornerInts);
    corner_pass_->bind(cb, *set_);
    ModeConstants mode = mode_;
    mode.patch_base = static_cast<std::int32_t>(count);
    vkCmdPushConstants(cb, corner_pass_->layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof mode,
                       &mode);
    vkCmdDispatch(cb, (count + kCornerGroup - 1) / kCornerGroup, 1, 1);
    memory_barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                   VK_PIPELINE_STAGE_TESSELLATION_CONTROL_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
  }

  void record_draws(VkCommandBuffer cb, const Pipelines& pipelines,
                    const std::vector<Draw>& draws) const {
    vk_ksquad::record_draws(cb, layout_, *set_, pipelines, draws, mode_, draw_stages());
  }

  VkShaderStageFlags draw_stages() const {
    return kModeStages | (settings_.gs || settings_.nonuniform ? VK_SHADER_STAGE_GEOMETRY_BIT : 0);
  }
  // The stages that write the capture buffers.
  VkPipelineStageFlags writing_stages() const {
    return VK_PIPELINE_STAGE_TESSELLATION_EVALUATION_SHADER_BIT |
           (settings_.gs || settings_.nonuniform ? VK_PIPELINE_STAGE_GEOMETRY_SHADER_BIT : 0);
  }
  std::uint32_t image_width() const { return static_cast<std::uint32_t>(settings_.viewport[0]); }
  std::uint32_t image_height() const { return static_cast<std::uint32_t>(settings_.viewport[1]); }

  vulkan::Device device_;
  vulkan::QueryPools queries_;
  vulkan::TrimClassifier classifier_;
  trim_direct::Settings trim_settings_;
  bool classified_ = false;
  bool classifying_chosen_samples_ = false;  // span grids: see classify()
  DeviceInfo record_;
  std::unique_ptr<vulkan::StorageSet> set_;  // created once, in create_pipeline()
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  std::unique_ptr<vk_ksquad::CaptureTarget> capture_;  // created once, in create_pipeline()
  Pipelines capture_pipelines_, raster_pipelines_;     // created once per degree pair, kept
  std::vector<Draw> draws_, raster_draws_;             // capture: patches with samples; raster: all
  std::unique_ptr<vk_ksquad::RasterTarget> raster_;    // made on render()'s first call

  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  vk_ksquad::HostTables tables_;
  std::vector<float> params_;
  std::vector<float> corners_;
  vulkan::Buffer trim_surfaces_buf_;
  vulkan::Buffer surfaces_buf_, patches_buf_, constants_buf_, points_, params_buf_, positions_,
      corners_buf_, levels_, normals_, sample_params_, corner_jobs_buf_;
  vulkan::Buffer ksdice_;         // nonuniform: the geometry stage's KSDie records
  std::vector<int> corner_jobs_;  // kCornerInts per corner (ksquad_corners.comp)
  std::unique_ptr<vulkan::ComputePipeline> corner_pass_;  // ksquad_corners.comp
  std::size_t patch_count_ = 0, total_ = 0, surface_count_ = 0, region_ = 0;
  KsquadSettings settings_;
  ModeConstants mode_{};
  vk_ksquad::Corners corner_table_;
  std::optional<double> evaluate_s_;
  KsquadStatistics stats_;
};

}  // namespace

std::unique_ptr<Strategy> make_vk_ksquad(const StrategyOptions& options) {
  try {
    return std::make_unique<VkKsquad>(vulkan::device_option(options), ksquad_settings(options),
                                      trim_direct::settings_from(options, "vk-ksquad"));
  } catch (const vulkan::MissingFeature& e) {
    throw std::runtime_error(std::string("unavailable: ") + e.what());
  }
}

namespace {
const VkKsquad& as_vk_ksquad(const Strategy& strategy) {
  const auto* vk = dynamic_cast<const VkKsquad*>(&strategy);
  if (!vk) throw std::invalid_argument("not a vk-ksquad strategy");
  return *vk;
}
}  // namespace

KsquadStatistics ksquad_statistics(const Strategy& strategy) {
  return as_vk_ksquad(strategy).statistics();
}

std::vector<CapturedEdge> ksquad_captured_edges(const Strategy& strategy) {
  return as_vk_ksquad(strategy).captured_edges();
}

std::vector<KsdieRecord> ksquad_ksdice(const Strategy& strategy) {
  return as_vk_ksquad(strategy).ksdice();
}

std::vector<PatchLevels> ksquad_patch_levels(const Strategy& strategy) {
  return as_vk_ksquad(strategy).patch_levels();
}

bool ksquad_render(Strategy& strategy) {
  return const_cast<VkKsquad&>(as_vk_ksquad(strategy)).render();
}

std::size_t ksquad_rendered_pixels(const Strategy& strategy) {
  return as_vk_ksquad(strategy).rendered_pixels();
}

StrategyEntry vk_ksquad_entry() {
  return {"vk-ksquad",
          "003 §2-4 (RPNS 2014): KSQuads in Vulkan tessellation stages, stair basis",
          "strategy",
          [] { return vulkan::probe(ksquad_requirements()); },
          ksquad_capabilities,
          make_vk_ksquad};
}

}  // namespace nurbs
