// vk-ksquad (003 §2-4). Where the paper is ambiguous or D3D11-specific, and what we chose:
//  * D3D11 hull / domain shaders -> Vulkan tessellation control / evaluation shaders; the
//    paper's vertex buffer of KSQuad ids -> no vertex input at all: one vertex per patch and
//    gl_PrimitiveID as the row of the Info-KSQuad table (003 Fig 8's first level of indirection;
//    the surface table is the second).
//  * "Per-KSQuad constant denominators computed once" (§3.2): computed once per non-empty span
//    and direction per prepare, on the device by a compute pass (ksquad_constants.comp: the
//    single-source stair_constants compiled as GLSL, from the knots as floats; vk-constants=device,
//    the default, as 003 §1 asks: no precomputation on the CPU) or on the host by the tested C++
//    build of the same function (vk-constants=host, kept to compare), and read from a storage
//    buffer; KSQuads sharing a span share its constants. They depend on the knots alone, so a
//    deforming frame never recomputes them.
//  * Uniform mode (vk-mode=uniform, our mapping for the harness's requested grids and span grids;
//    003 §4's mapping that "obtains a uniform result" is the adaptive one below): the levels of a
//    patch are the segment counts of its u and v runs. Span grid T: the tessellator chooses the
//    samples -- its (T+1)x(T+1) lattice per KSQuad (docs/design.md §Sampling: span grid), the
//    parameter blended from the span's knots by gl_TessCoord (ksquad.tese span_parameter) and
//    returned with the position, so the samples are the float rounding of the requested ones. Grid
//    (the paper has no grids; our mapping): gl_TessCoord indexes the KSQuad's sub-grid of requested
//    samples, evaluated at exactly the requested parameters; render() instead draws every patch
//    over its span share from the knots (patches share their boundary vertices on the knot lines;
//    every non-empty span pair is a patch, samples or not). Runs past
//    maxTessellationGenerationLevel are cut into several patches (patches.h), never clamped.
//  * Capture: storage-buffer writes from the evaluation stage (vertexPipelineStoresAndAtomics),
//    rasterization discarded; transform feedback would need a vertex order the tessellator does
//    not specify.
//  * Adaptive mode (003 §4's second mapping, the one the paper calls uniform; §3.1's local area
//    average, eq. 3): the KSQuad corners S(x_k, y_l), one table
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
#include "strategies/vk_ksquad/vk_ksquad_class.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"
#include "strategies/vulkan/vk_device.h"
#include "strategies/vulkan/vk_trim_classify.h"

namespace nurbs::embedded {
extern const std::string_view vk_ksquad_corners_comp;
extern const std::string_view vk_ksquad_constants_comp;
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
using vk_ksquad::Mapping;
using vk_ksquad::ModeConstants;
using vulkan::memory_barrier;

constexpr int kConstantFloats = kStairConstantReals;
static_assert(sizeof(StairConstants<float>) == kConstantFloats * sizeof(float),
              "stair_basis.h reads StairConstants<float> as packed floats");
constexpr int kBuffers = 15;
// Bindings 9..11 are the fragment stage's trim test (ksquad.frag): the classifier's tables and
// one row per surface (VkKsquad::trim_surface_rows); 12 is the span grid's sample parameters; 14
// the nonuniform mapping's KSDie records (ksquad_nonuniform.glsl).
constexpr int kFirstTrimBinding = 9, kTrimBindings = 3;

// The stages that read the tables and the push constants; the GS mapping (ksquad.geom) adds its
// stage only where the geometry-shader feature is enabled (VkKsquad::draw_stages), the corner pass
// (ksquad_corners.comp) reads the same set through its own layout.
constexpr VkShaderStageFlags kModeStages =
    VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT;
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

}  // namespace

namespace vk_ksquad {

Capabilities VkKsquad::capabilities() const {
  return vk_ksquad_descriptor().capabilities;
}

VkKsquad::VkKsquad(int device_index, const KsquadSettings& settings,
                   const trim_direct::Settings& trim)
    : device_(device_index, ksquad_requirements(settings.geometry_stage())),
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
  if (settings_.is(Mapping::gs)) check_gs_limits();
  if (settings_.is(Mapping::nonuniform)) check_nonuniform_limits();
  // the report labels vk-ksquad's series by the mapping
  record_.details["vk_mode"] = vk_ksquad::mapping_name(settings_.mapping);
  record_.details["vk_constants"] = settings_.device_constants ? "device" : "host";
  if (settings_.camera_levels()) {
    record_.details["vk_corners"] = settings_.device_corners ? "device" : "host";
    record_.details["vk_eq3"] = settings_.eq3_literal ? "literal" : "edge";
    record_.details["vk_thresholds"] = settings_.surface_thresholds ? "surface" : "global";
  }
  if (settings_.is(Mapping::nonuniform)) {
    record_.details["vk_epsilon"] = fmt::format("{}", settings_.epsilon);
    record_.details["vk_eta"] = fmt::format("{}", settings_.eta);
    record_.details["vk_max_level"] = std::to_string(settings_.max_level);
  }
  create_pipeline();
}

void VkKsquad::prepare_checked(const Scene& scene, const EvalRequest& request) {
  const vulkan::UploadCount uploads(device_, record_);
  if (settings_.is(Mapping::gs)) refuse_gs(request);
  const bool trimmed = std::any_of(scene.surfaces.begin(), scene.surfaces.end(),
                                   [](const Surface& s) { return s.trim.has_value(); });
  if (settings_.camera_levels() && trimmed)
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

void VkKsquad::evaluate() {
  device_.submit_and_wait([&](VkCommandBuffer cb) {
    if (settings_.camera_levels()) {
      // Unwritten capture slots read back as NaN (a quiet NaN's bits in every word); nonuniform:
      // KSDice the tessellator did not start keep status 0.
      vkCmdFillBuffer(cb, positions_.handle(), 0, VK_WHOLE_SIZE, 0x7fc00000u);
      if (settings_.is(Mapping::nonuniform))
        vkCmdFillBuffer(cb, ksdice_.handle(), 0, VK_WHOLE_SIZE, 0u);
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
  times_.evaluate_s = queries_.elapsed_s();
  const auto counts = queries_.statistics();
  stats_.control_patches = counts.size() > 0 ? counts[0] : 0;
  stats_.evaluation_invocations = counts.size() > 1 ? counts[1] : 0;
}

EvalResult VkKsquad::read_back() {
  EvalResult out;
  read_back_into(out);
  return out;
}

// The uniform mapping reads into out's kept storage; the camera-driven mappings choose their
// samples anew on every evaluation, so their results are built afresh.
void VkKsquad::read_back_into(EvalResult& out) {
  if (settings_.is(Mapping::nonuniform))
    out = read_back_nonuniform();
  else if (settings_.camera_levels())
    out = read_back_adaptive();
  else
    read_back_uniform(out);
}

// Only the homogeneous control points change (same knots, degrees and samples): the tables
// and constants stay.
void VkKsquad::update_control_points(const Scene& scene) {
  const std::vector<float> points = homogeneous_points(scene);
  if (points.size() * sizeof(float) != points_.size())
    throw std::invalid_argument("vk-ksquad: update_control_points changed the control nets");
  points_.write(points.data(), points.size() * sizeof(float));
  if (settings_.camera_levels() && !settings_.device_corners) {  // the corners move with the points
    corners_ = vk_ksquad::corner_table(scene, true).rows;
    corners_buf_.write(corners_.data(), corners_.size() * sizeof(float));
  }
}

// 003 §4 end to end: the same patches drawn with rasterization into an offscreen image (the
// camera of the adaptive settings; fitted to the scene by default), positions never stored.
// Returns when the device is done; the runner times it as the `render` phase.
bool VkKsquad::render() {
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
std::size_t VkKsquad::rendered_pixels() const {
  const std::optional<RenderedImage> image = read_image();
  if (!image) return 0;
  std::size_t covered = 0;
  for (std::size_t p = 0; p < image->rgba.size(); p += 4)
    covered += image->rgba[p] != 0 || image->rgba[p + 1] != 0 || image->rgba[p + 2] != 0 ||
               image->rgba[p + 3] != 0;
  return covered;
}

std::optional<RenderedImage> VkKsquad::read_image() const {
  if (!raster_) return std::nullopt;
  return raster_->read();
}

std::vector<float> VkKsquad::homogeneous_points(const Scene& scene) {
  std::vector<float> points;
  for (const Surface& s : scene.surfaces) {
    const SurfaceNet<float> net(s);
    for (const Vec4<float>& h : net.homogeneous) points.insert(points.end(), h.begin(), h.end());
  }
  return points;
}

// The adaptive camera: given, or fitted to the scene's control-point bounding sphere.
void VkKsquad::set_mode(const Scene& scene) {
  mode_ = {};
  mode_.adaptive = settings_.camera_levels() ? 1 : 0;
  mode_.max_level = settings_.max_level;
  mode_.pieces = settings_.pieces;
  mode_.region = static_cast<std::int32_t>(region_);
  mode_.normals = request_.normals ? 1 : 0;
  mode_.span_grid = span_grid_samples() ? 1 : 0;
  // nonuniform: the control stage's lower level (ksquad.tesc)
  mode_.mu = static_cast<float>(settings_.is(Mapping::nonuniform) ? settings_.mu * (1 << kNuDepth)
                                                                  : settings_.mu);
  mode_.nonuniform = settings_.is(Mapping::nonuniform) ? 1 : 0;
  mode_.eq3_literal = settings_.eq3_literal ? 1 : 0;
  mode_.epsilon = static_cast<float>(settings_.epsilon);
  mode_.eta = static_cast<float>(settings_.eta);
  mode_.viewport[0] = static_cast<float>(settings_.viewport[0]);
  mode_.viewport[1] = static_cast<float>(settings_.viewport[1]);
  const auto m = vk_ksquad::scene_camera(scene, settings_);
  std::copy(m.begin(), m.end(), mode_.view_projection);
}

// Surface table, per-span stair constants and the Info-KSQuad table (one row per patch).
void VkKsquad::build_tables(const Scene& scene) {
  vk_ksquad::SurfaceTable table = vk_ksquad::surface_table(scene, samples_);
  tables_.surfaces = std::move(table.surfaces);
  if (settings_.is(Mapping::nonuniform)) {
    const std::vector<int> friendless = vk_ksquad::friendless_sides(scene);
    for (std::size_t i = 0; i < friendless.size(); ++i)
      tables_.surfaces[i * kSurfaceInts + vk_ksquad::kSurfaceFriendless] = friendless[i];
  }
  if (settings_.camera_levels() && settings_.surface_thresholds) {
    const std::vector<double> scales = vk_ksquad::surface_threshold_scales(
        scene, vk_ksquad::scene_camera(scene, settings_), settings_.viewport);
    for (std::size_t i = 0; i < scales.size(); ++i)
      tables_.surfaces[i * kSurfaceInts + vk_ksquad::kSurfaceThresholdScale] =
          std::bit_cast<int>(static_cast<float>(scales[i]));
  }
  tables_.patches.clear();
  tables_.constants.clear();
  knot_table_.clear();
  constant_jobs_.clear();
  params_ = std::move(table.params);
  total_ = table.total;
  // (surface, direction, span) -> offset of its constants in floats.
  std::map<std::tuple<int, int, int>, int> constant_of;
  std::map<std::pair<int, int>, std::size_t> knot_of;  // (surface, direction) -> knot_table_
  const auto constants = [&](int surface, int direction, int span) {
    const auto key = std::make_tuple(surface, direction, span);
    if (auto it = constant_of.find(key); it != constant_of.end()) return it->second;
    const Surface& s = scene.surfaces[surface];
    const std::vector<double>& k64 = direction == 0 ? s.knots_u : s.knots_v;
    const std::vector<float> k32(k64.begin(), k64.end());
    const int degree = direction == 0 ? s.degree_u : s.degree_v;
    const int offset = static_cast<int>(tables_.constants.size());
    if (settings_.device_constants) {
      // ksquad_constants.comp computes them from the knots (as floats) once per prepare; the
      // host keeps only the copied knot window, which its own readers (adaptive_edges) use.
      const auto [knots, added] = knot_of.try_emplace({surface, direction}, knot_table_.size());
      if (added) knot_table_.insert(knot_table_.end(), k32.begin(), k32.end());
      constant_jobs_.insert(constant_jobs_.end(),
                            {static_cast<int>(knots->second), degree, span, offset});
      tables_.constants.resize(tables_.constants.size() + kConstantFloats, 0.0f);
      for (int t = 0; t < 2 * degree; ++t)
        tables_.constants[static_cast<std::size_t>(offset + SB_KNOTS + t)] =
            k32[static_cast<std::size_t>(span - degree + 1 + t)];
    } else {
      StairConstants<float> c{};
      stair_constants(span, degree, k32.data(), c);
      const float* f = reinterpret_cast<const float*>(&c);
      tables_.constants.insert(tables_.constants.end(), f, f + kConstantFloats);
    }
    constant_of.emplace(key, offset);
    return offset;
  };
  const int cap = static_cast<int>(device_.limits().maxTessellationGenerationLevel);
  stats_ = {};
  stats_.level_cap = settings_.camera_levels() ? settings_.max_level : cap;
  surface_count_ = scene.surfaces.size();
  // Adaptive: one patch per KSQuad of the span grid (the tessellator chooses the samples).
  Sampling one_per_span;
  one_per_span.mode = SamplingMode::span_grid;
  one_per_span.span_steps = 1;
  const auto quads =
      settings_.camera_levels()
          ? ksquad::build_ksquads<float>(scene, sample_parameters(scene, one_per_span),
                                         one_per_span)
          : (span_grid_samples() ? ksquad::build_ksquads<float>(scene, samples_, request_.sampling)
                                 : vk_ksquad::grid_ksquads(scene, samples_));
  corner_table_ = settings_.camera_levels()
                      ? vk_ksquad::corner_table(scene, !settings_.device_corners)
                      : vk_ksquad::Corners{};
  corners_ = corner_table_.rows;
  corner_jobs_.clear();
  if (settings_.camera_levels() && settings_.device_corners)
    for (const auto& [surface, span_u, span_v, end_u, end_v] : corner_table_.spans)
      corner_jobs_.insert(corner_jobs_.end(),
                          {surface * kSurfaceInts, span_u, span_v, constants(surface, 0, span_u),
                           constants(surface, 1, span_v), end_u, end_v, 0});
  // A knot span non-empty in double but empty in float (knots closer than a float ulp:
  // linkrods.step's face 33, 1.8e-8 apart near v = -3.61) has stair constants 1 / 0. Every
  // parameter of it rounds to the one float x_i, and ksquad::runs_of_span_grid already gives its
  // run the span A2.1 on the float knots finds for x_i (non-empty in float, the one the
  // reference's search takes for that float). The uniform span-grid mapping must then not spread
  // the run over that span: it evaluates all of it at x_i, the span's start (share 0) or, at the
  // domain's end, its end (1); -1 = an ordinary run. (Grids are evaluated at their own
  // parameters; adaptive mode tessellates the whole KSQuad of the span it is given.)
  const bool collapsible = !settings_.camera_levels() && span_grid_samples();
  const auto collapsed_share = [&](int surface, int direction, const ksquad::SpanRun& run) {
    if (!collapsible || run.count < 2) return -1.0f;
    const std::vector<double>& params = direction == 0 ? samples_[surface].u : samples_[surface].v;
    const Surface& s = scene.surfaces[surface];
    const std::vector<double>& knots = direction == 0 ? s.knots_u : s.knots_v;
    const float first = static_cast<float>(params[run.begin]);
    if (first != static_cast<float>(params[run.begin + run.count - 1])) return -1.0f;
    return first == static_cast<float>(knots[run.span]) ? 0.0f : 1.0f;
  };
  for (const ksquad::KSQuad& q : quads) {
    const Surface& s = scene.surfaces[q.surface];
    const float share_u = collapsed_share(q.surface, 0, q.u);
    const float share_v = collapsed_share(q.surface, 1, q.v);
    const int cu = constants(q.surface, 0, q.u.span), cv = constants(q.surface, 1, q.v.span);
    int c[4] = {0, 0, 0, 0};
    if (settings_.camera_levels())
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
    const int piece_cap = settings_.camera_levels() ? std::numeric_limits<int>::max() : cap;
    const int pieces = settings_.camera_levels() ? settings_.pieces * settings_.pieces : 1;
    for (const ksquad::SpanRun& a : vk_ksquad::split_run(q.u, piece_cap))
      for (const ksquad::SpanRun& b : vk_ksquad::split_run(q.v, piece_cap))
        for (int piece = 0; piece < pieces; ++piece) {
          const int lu = vk_ksquad::run_level(a), lv = vk_ksquad::run_level(b);
          auto [u_lo, u_hi] = vk_ksquad::piece_share(q.u, a);
          auto [v_lo, v_hi] = vk_ksquad::piece_share(q.v, b);
          if (share_u >= 0) u_lo = u_hi = share_u;
          if (share_v >= 0) v_lo = v_hi = share_v;
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
      settings_.camera_levels()
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

void VkKsquad::upload_tables(const Scene& scene) {
  const int level = settings_.max_level;
  region_ = settings_.camera_levels()
                ? static_cast<std::size_t>(4 * (level + 1) + (level - 1) * (level - 1))
                : 0;
  set_mode(scene);
  const std::size_t ksdie_slots = settings_.is(Mapping::nonuniform)
                                      ? patch_count_ * vk_ksquad::ksdie_slots(settings_.max_level)
                                      : 0;
  const std::size_t output_floats =
      settings_.is(Mapping::nonuniform)
          ? ksdie_slots * kNuLattice * kNuLattice * kNuVertexFloats
          : (settings_.camera_levels() ? patch_count_ * region_ * kSlotFloats : total_ * 3);
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
      settings_.is(Mapping::nonuniform)
          ? 0
          : (settings_.camera_levels() ? patch_count_ * region_ : total_);
  normals_ = vulkan::Buffer(device_, (request_.normals ? normal_slots * 3 : 0) * sizeof(float),
                            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output normals");
  sample_params_ = vulkan::Buffer(device_, (span_grid_samples() ? total_ * 2 : 0) * sizeof(float),
                                  VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output sample parameters");
  set_->write({&surfaces_buf_, &patches_buf_, &constants_buf_, &points_, &params_buf_, &positions_,
               &corners_buf_, &levels_, &normals_, &classifier_.reals(), &classifier_.ints(),
               &trim_surfaces_buf_, &sample_params_, &corner_jobs_buf_, &ksdice_});
  compute_constants();
}

constexpr std::uint32_t kConstantsGroup = 64;  // ksquad_constants.comp: local_size_x

// vk-constants=device: the stair constants of every (surface, direction, span) by the constants
// pass, then a barrier so every later stage that reads them sees them (later submissions on the
// same queue are in the barrier's second scope).
void VkKsquad::compute_constants() {
  if (constant_jobs_.empty()) return;
  knots_buf_ = storage(knot_table_, "knot vectors");
  constant_jobs_buf_ = storage(constant_jobs_, "stair constant jobs");
  constants_set_->write({&knots_buf_, &constant_jobs_buf_, &constants_buf_});
  const auto count = static_cast<std::int32_t>(constant_jobs_.size() / 4);
  device_.submit_and_wait([&](VkCommandBuffer cb) {
    constants_pass_->bind(cb, *constants_set_);
    vkCmdPushConstants(cb, constants_pass_->layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof count,
                       &count);
    vkCmdDispatch(cb, (static_cast<std::uint32_t>(count) + kConstantsGroup - 1) / kConstantsGroup,
                  1, 1);
    memory_barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                   VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                   VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_HOST_READ_BIT);
  });
}

// Once per strategy (STYLE.md: compiled shaders are created once, never in evaluate()).
void VkKsquad::create_pipeline() {
  std::vector<VkShaderStageFlags> stages(kBuffers, draw_stages() | VK_SHADER_STAGE_COMPUTE_BIT);
  for (int k = kFirstTrimBinding; k < kFirstTrimBinding + kTrimBindings; ++k)
    stages[k] = VK_SHADER_STAGE_FRAGMENT_BIT;
  set_ = std::make_unique<vulkan::StorageSet>(device_, stages);
  layout_ = vk_ksquad::make_layout(device_, *set_, draw_stages());
  corner_pass_ = std::make_unique<vulkan::ComputePipeline>(
      device_, *set_, static_cast<std::uint32_t>(sizeof(ModeConstants)),
      embedded::vk_ksquad_corners_comp, "ksquad_corners.comp");
  constants_set_ = std::make_unique<vulkan::StorageSet>(
      device_, std::vector<VkShaderStageFlags>(3, VK_SHADER_STAGE_COMPUTE_BIT));
  constants_pass_ = std::make_unique<vulkan::ComputePipeline>(
      device_, *constants_set_, static_cast<std::uint32_t>(sizeof(std::int32_t)),
      embedded::vk_ksquad_constants_comp, "ksquad_constants.comp");

  capture_ = std::make_unique<vk_ksquad::CaptureTarget>(device_);
}

VkPipeline VkKsquad::pipeline_for(Pipelines& pipelines, bool raster, const Draw& draw) {
  auto& pipeline = pipelines[{draw.du, draw.dv}];
  if (!pipeline)
    pipeline = vk_ksquad::make_pipeline(
        device_, vk_ksquad::ksquad_shaders(settings_.mapping), layout_, raster,
        vk_ksquad::mapping_stages(settings_.mapping), raster ? raster_->pass() : capture_->pass(),
        draw.du, draw.dv, image_width(), image_height());
  return pipeline;
}

VkShaderStageFlags VkKsquad::draw_stages() const {
  return kModeStages | (settings_.geometry_stage() ? VK_SHADER_STAGE_GEOMETRY_BIT : 0);
}

// The stages that write the capture buffers.
VkPipelineStageFlags VkKsquad::writing_stages() const {
  return VK_PIPELINE_STAGE_TESSELLATION_EVALUATION_SHADER_BIT |
         (settings_.geometry_stage() ? VK_PIPELINE_STAGE_GEOMETRY_SHADER_BIT : 0);
}

}  // namespace vk_ksquad

std::unique_ptr<Strategy> make_vk_ksquad(const StrategyOptions& options) {
  try {
    return std::make_unique<vk_ksquad::VkKsquad>(vulkan::device_option(options),
                                                 ksquad_settings(options),
                                                 trim_direct::settings_from(options, "vk-ksquad"));
  } catch (const vulkan::MissingFeature& e) {
    throw std::runtime_error(std::string("unavailable: ") + e.what());
  }
}

namespace {
const vk_ksquad::VkKsquad& as_vk_ksquad(const Strategy& strategy) {
  const auto* vk = dynamic_cast<const vk_ksquad::VkKsquad*>(&strategy);
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
  return const_cast<vk_ksquad::VkKsquad&>(as_vk_ksquad(strategy)).render();
}

std::size_t ksquad_rendered_pixels(const Strategy& strategy) {
  return as_vk_ksquad(strategy).rendered_pixels();
}

StrategyEntry vk_ksquad_entry() {
  return make_entry(
      vk_ksquad_descriptor(), [] { return vulkan::probe(ksquad_requirements()); }, make_vk_ksquad);
}

}  // namespace nurbs
