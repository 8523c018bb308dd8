// vk-bezier (see vk_bezier.h). What it shares with vk-ksquad and why:
//  * The pipeline shape: one tessellation patch per rational Bézier patch -- the decomposition's
//    patches are exactly RPNS's KSQuads, one per non-empty span pair (003 §2) -- so the patch
//    table, the control stage (ksquad.tesc, uniform mode), the runs of samples per span and their
//    cutting past maxTessellationGenerationLevel, the draws per degree pair bounded by
//    vk-vertices-per-draw and the capture into storage buffers are vk-ksquad's own code. Only the
//    evaluation stage differs: a Bézier patch evaluated at its local parameter (bezier.tese)
//    instead of the NURBS evaluated with the stair basis. A like-for-like comparison of the two
//    therefore measures what 003 §2 says separates them: the decomposition and the larger upload.
//  * Samples: a grid sample is evaluated in the Bézier patch of the knot span A2.1 puts it in on
//    the float knots (ksquad::runs_of_grid, as vk-ksquad's uniform mapping), at the requested
//    parameter; a span grid's are the tessellator's (ksquad_tables.glsl share_parameter), returned
//    with the positions.
//  * The decomposition runs in double (as cpu-bezier's, a CPU converter holding the model in
//    double, 003 Fig. 3(a)); its homogeneous points are rounded to float once, on upload,
//    relative to their patch's origin (decompose_all).
#include "strategies/vk_bezier/vk_bezier.h"

#include <fmt/format.h>

#include <bit>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "reference/bezier_decomposition.h"
#include "reference/nurbs_math.h"
#include "reference/validation.h"
#include "strategies/ksquad/ksquad_table.h"
#include "strategies/vk_ksquad/ksquad_layout.h"
#include "strategies/vk_ksquad/ksquad_pipeline.h"
#include "strategies/vk_ksquad/ksquad_settings.h"
#include "strategies/vk_ksquad/patches.h"
#include "strategies/vk_ksquad/uniform_mapping.h"
#include "strategies/vulkan/vk_device.h"

namespace nurbs::embedded {
extern const std::string_view vk_bezier_tese;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

using vk_ksquad::kPatchInts;
using vk_ksquad::kSurfaceInts;

// ksquad_tables.glsl's bindings 0..12. The ones bezier.tese reads or writes: 0 surfaces,
// 1 patches, 3 Bézier points, 4 parameters, 5 positions, 8 normals, 12 the span grid's
// parameters; 6 and 7
// are statically used by the shared control stage's adaptive branch (never taken here) and get a
// placeholder, as do the rest.
constexpr int kBuffers = 13;
constexpr VkShaderStageFlags kStages =
    VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT;

vulkan::Requirements bezier_requirements() {
  vulkan::Requirements r;
  r.tessellation_shader = true;
  r.vertex_pipeline_stores = true;
  return r;
}

// One surface: its net in double (the decomposition's input, kept so a frame only moves points)
// and the decomposition's output and scratch, reused frame after frame.
struct Decomposed {
  SurfaceNet<double> net;
  BezierPatches<double> patches;
  DecompositionScratch<double> scratch;
  std::vector<int> segment_of_span_u, segment_of_span_v;
  explicit Decomposed(const Surface& s) : net(s) {}
};

class VkBezier final : public Strategy {
 public:
  VkBezier(int device_index, std::uint64_t vertices_per_draw)
      : device_(device_index, bezier_requirements()),
        queries_(device_, 0),
        vertices_per_draw_(vertices_per_draw) {
    record_ = device_.record();
    // Once per strategy (STYLE.md: compiled shaders are created once, never in evaluate()).
    set_ = std::make_unique<vulkan::StorageSet>(device_,
                                                std::vector<VkShaderStageFlags>(kBuffers, kStages));
    layout_ = vk_ksquad::make_layout(device_, *set_, kStages);
    capture_ = std::make_unique<vk_ksquad::CaptureTarget>(device_);
    placeholder_ = vulkan::Buffer(device_, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "placeholder");
  }
  ~VkBezier() override {
    vkDeviceWaitIdle(device_.handle());
    for (const auto& [degrees, pipeline] : pipelines_)
      vkDestroyPipeline(device_.handle(), pipeline, nullptr);
    if (layout_) vkDestroyPipelineLayout(device_.handle(), layout_, nullptr);
  }

  std::string_view name() const override { return "vk-bezier"; }
  Capabilities capabilities() const override { return vk_bezier_descriptor().capabilities; }
  DeviceInfo device() const override { return record_; }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    const vulkan::UploadCount uploads(device_, record_);
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    surfaces_.clear();
    surfaces_.reserve(scene.surfaces.size());
    for (const Surface& s : scene.surfaces) surfaces_.emplace_back(s);
    decompose_all();
    build_tables(scene);
    vk_ksquad::SurfaceTable table = vk_ksquad::surface_table(scene, samples_);
    total_ = table.total;
    surfaces_buf_ = storage(table.surfaces, "surface table");
    params_buf_ = storage(table.params, "parameters");
    patches_buf_ = storage(patches_, "patch table");
    points_buf_ = storage(points_, "Bézier points");
    positions_ = vulkan::Buffer(device_, total_ * 3 * sizeof(float),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output positions");
    normals_ = vulkan::Buffer(device_, (request.normals ? total_ * 3 : 0) * sizeof(float),
                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output normals");
    sample_params_ = vulkan::Buffer(device_, (span_grid() ? total_ * 2 : 0) * sizeof(float),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output sample parameters");
    const vulkan::Buffer* none = &placeholder_;
    set_->write({&surfaces_buf_, &patches_buf_, none, &points_buf_, &params_buf_, &positions_, none,
                 none, &normals_, none, none, none, &sample_params_});
    mode_ = {};
    mode_.span_grid = span_grid() ? 1 : 0;
    mode_.normals = request.normals ? 1 : 0;
    for (const vk_ksquad::Draw& draw : draws_) {
      VkPipeline& pipeline = pipelines_[{draw.du, draw.dv}];
      if (!pipeline) {
        vk_ksquad::PipelineShaders shaders = vk_ksquad::ksquad_shaders();
        shaders.tese = embedded::vk_bezier_tese;
        pipeline = vk_ksquad::make_pipeline(device_, shaders, layout_, false,
                                            vk_ksquad::Stages::tessellation, capture_->pass(),
                                            draw.du, draw.dv, 1, 1);
      }
    }
  }

  // The baseline's per-frame cost as 003 §2 describes it: the Bézier form cannot follow moved
  // NURBS control points, so every frame runs the whole decomposition (A5.7) of every surface
  // again and uploads all of its Bézier points -- (p+1)(q+1) per non-empty span pair, against
  // vk-ksquad's re-upload of the NURBS net alone. The patch table, knots and samples stay.
  void update_control_points(const Scene& scene) override {
    if (scene.surfaces.size() != surfaces_.size())
      throw std::invalid_argument(
          fmt::format("vk-bezier: update_control_points with {} surfaces, prepared with {}",
                      scene.surfaces.size(), surfaces_.size()));
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      const Surface& in = scene.surfaces[i];
      SurfaceNet<double>& net = surfaces_[i].net;
      if (in.count_u != net.count_u || in.count_v != net.count_v || in.degree_u != net.degree_u ||
          in.degree_v != net.degree_v || in.knots_u != net.knots_u || in.knots_v != net.knots_v)
        throw std::invalid_argument(
            fmt::format("vk-bezier: update_control_points: surface '{}' changed its degrees, "
                        "counts or knots (only points and weights may move)",
                        in.name));
      for (std::size_t k = 0; k < in.points.size(); ++k) {
        const double w = in.weights[k];  // as SurfaceNet<double> forms it
        net.homogeneous[k] = {in.points[k][0] * w, in.points[k][1] * w, in.points[k][2] * w, w};
      }
    }
    decompose_all();
    points_buf_.write(points_.data(), points_.size() * sizeof(float));
  }

  void evaluate() override {
    device_.submit_and_wait([&](VkCommandBuffer cb) {
      queries_.reset(cb);
      queries_.begin(cb);
      capture_->begin(cb);
      vk_ksquad::record_draws(cb, layout_, *set_, pipelines_, draws_, mode_, kStages);
      vkCmdEndRenderPass(cb);
      queries_.end(cb);
      vulkan::memory_barrier(cb, VK_PIPELINE_STAGE_TESSELLATION_EVALUATION_SHADER_BIT,
                             VK_ACCESS_SHADER_WRITE_BIT,
                             VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
    });
    times_.evaluate_s = queries_.elapsed_s();
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  void read_back_into(EvalResult& out) override {
    vk_ksquad::read_uniform_capture(out, samples_, positions_,
                                    span_grid() ? &sample_params_ : nullptr,
                                    request_.normals ? &normals_ : nullptr);
  }

  DeviceTimes device_times() const override { return times_; }

 private:
  bool span_grid() const { return request_.sampling.mode == SamplingMode::span_grid; }

  template <typename V>
  vulkan::Buffer storage(const std::vector<V>& data, const char* what) {
    vulkan::Buffer b(device_, data.size() * sizeof(V), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, what);
    b.write(data.data(), data.size() * sizeof(V));
    return b;
  }

  // A5.7 on every surface's current net (double), then every Bézier patch as float homogeneous
  // vec4s, surface after surface in BezierPatches order: its origin (its first control point, in
  // float; w unused), then its points relative to it. Why relative (cpu-bezier's reason): knot
  // insertion packs the Bézier points closely, and their float rounding far from the origin tilts
  // normals (far-origin, |x| = 1e4: 1.35 degrees with absolute points); the Bézier form is affine
  // invariant, so S = O + sum B w (P - O) / sum B w exactly.
  void decompose_all() {
    points_.clear();
    first_point_.clear();
    for (Decomposed& d : surfaces_) {
      decompose_surface(d.net, d.patches, d.scratch);
      first_point_.push_back(points_.size() / 4);
      const std::size_t per_patch = d.patches.points_per_patch();
      for (std::size_t g = 0; g < d.patches.patch_count(); ++g) {
        const Vec4<double>* from = d.patches.points.data() + g * per_patch;
        float origin[3];
        for (int c = 0; c < 3; ++c) origin[c] = static_cast<float>(from[0][c] / from[0][3]);
        points_.insert(points_.end(), {origin[0], origin[1], origin[2], 0.0f});
        for (std::size_t k = 0; k < per_patch; ++k) {
          const double w = from[k][3];
          for (int c = 0; c < 3; ++c)
            points_.push_back(static_cast<float>(from[k][c] - double(origin[c]) * w));
          points_.push_back(static_cast<float>(w));
        }
      }
    }
  }

  // The patch table (ksquad_tables.glsl layout, the fields bezier.tese reads; see there): one row
  // per Bézier patch holding samples, or per piece of one where a run passes the tessellator's
  // cap, then grouped into draws.
  void build_tables(const Scene& scene) {
    for (std::size_t i = 0; i < surfaces_.size(); ++i) {
      Decomposed& d = surfaces_[i];
      d.segment_of_span_u.assign(d.net.count_u, -1);
      d.segment_of_span_v.assign(d.net.count_v, -1);
      for (int g = 0; g < d.patches.segments_u; ++g) d.segment_of_span_u[d.patches.spans_u[g]] = g;
      for (int h = 0; h < d.patches.segments_v; ++h) d.segment_of_span_v[d.patches.spans_v[h]] = h;
    }
    const auto quads = span_grid()
                           ? ksquad::build_ksquads<float>(scene, samples_, request_.sampling)
                           : vk_ksquad::grid_ksquads(scene, samples_);
    const int cap = static_cast<int>(device_.limits().maxTessellationGenerationLevel);
    patches_.clear();
    for (const ksquad::KSQuad& q : quads) {
      const Surface& s = scene.surfaces[q.surface];
      const Decomposed& d = surfaces_[q.surface];
      const int g = d.segment_of_span_u[q.u.span], h = d.segment_of_span_v[q.v.span];
      if (g < 0 || h < 0)
        throw std::logic_error("vk-bezier: a run of samples in a span the decomposition skipped");
      const std::size_t stride = d.patches.points_per_patch() + 1;  // the origin, the points
      const std::size_t first = first_point_[q.surface] +
                                (static_cast<std::size_t>(g) * d.patches.segments_v + h) * stride +
                                1;
      const auto bits = [](double knot) { return std::bit_cast<int>(static_cast<float>(knot)); };
      // The next Bézier patch in u (v) for normals at the span's end knot: its offset and its
      // span's end knot; none at the domain's end or where the next span is empty in float.
      const auto next = [&](int segment, int segments, const std::vector<double>& breaks,
                            std::size_t step) -> std::pair<int, int> {
        if (segment + 1 >= segments ||
            !(static_cast<float>(breaks[segment + 1]) < static_cast<float>(breaks[segment + 2])))
          return {0, 0};
        return {static_cast<int>(step), bits(breaks[segment + 2])};
      };
      const auto [next_u, end_u] =
          next(g, d.patches.segments_u, d.patches.breaks_u, d.patches.segments_v * stride);
      const auto [next_v, end_v] = next(h, d.patches.segments_v, d.patches.breaks_v, stride);
      for (const ksquad::SpanRun& a : vk_ksquad::split_run(q.u, cap))
        for (const ksquad::SpanRun& b : vk_ksquad::split_run(q.v, cap)) {
          const auto [u_lo, u_hi] = vk_ksquad::piece_share(q.u, a);
          const auto [v_lo, v_hi] = vk_ksquad::piece_share(q.v, b);
          const int row[kPatchInts] = {q.surface,
                                       q.u.span,
                                       q.v.span,
                                       static_cast<int>(first),
                                       0,
                                       a.begin,
                                       a.count,
                                       b.begin,
                                       b.count,
                                       vk_ksquad::run_level(a),
                                       vk_ksquad::run_level(b),
                                       0,
                                       bits(s.knots_u[q.u.span]),
                                       bits(s.knots_u[q.u.span + 1]),
                                       bits(s.knots_v[q.v.span]),
                                       bits(s.knots_v[q.v.span + 1]),
                                       next_u,
                                       next_v,
                                       end_u,
                                       end_v,
                                       std::bit_cast<int>(u_lo),
                                       std::bit_cast<int>(u_hi),
                                       std::bit_cast<int>(v_lo),
                                       std::bit_cast<int>(v_hi)};
          patches_.insert(patches_.end(), row, row + kPatchInts);
        }
    }
    vk_ksquad::sort_by_degrees(patches_, scene);
    draws_ = vk_ksquad::make_draws(patches_, scene, false, vertices_per_draw_, 0);
    record_.details["draws"] = std::to_string(draws_.size());
  }

  vulkan::Device device_;
  vulkan::QueryPools queries_;
  std::uint64_t vertices_per_draw_;
  DeviceInfo record_;
  std::unique_ptr<vulkan::StorageSet> set_;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  std::unique_ptr<vk_ksquad::CaptureTarget> capture_;
  vk_ksquad::Pipelines pipelines_;  // created once per degree pair, kept

  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::vector<Decomposed> surfaces_;
  std::vector<float> points_;             // what is uploaded: origins and Bézier points
  std::vector<std::size_t> first_point_;  // per surface, in vec4s
  std::vector<int> patches_;              // the patch table
  std::vector<vk_ksquad::Draw> draws_;
  std::size_t total_ = 0;
  vk_ksquad::ModeConstants mode_{};
  vulkan::Buffer placeholder_, surfaces_buf_, patches_buf_, points_buf_, params_buf_, positions_,
      normals_, sample_params_;
  DeviceTimes times_;  // the phases' last device times (device_times())
};

}  // namespace

StrategyEntry vk_bezier_entry() {
  return make_entry(
      vk_bezier_descriptor(), [] { return vulkan::probe(bezier_requirements()); },
      [](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
        try {
          return std::make_unique<VkBezier>(
              vulkan::device_option(options),
              vk_ksquad::vertices_per_draw_option(options, "vk-bezier"));
        } catch (const vulkan::MissingFeature& e) {
          throw std::runtime_error(std::string("unavailable: ") + e.what());
        }
      });
}

}  // namespace nurbs
