// vk-ksquad (003 §2-4). Where the paper is ambiguous or D3D11-specific, and what we chose:
//  * D3D11 hull / domain shaders -> Vulkan tessellation control / evaluation shaders; the
//    paper's vertex buffer of KSQuad ids -> no vertex input at all: one vertex per patch and
//    gl_PrimitiveID as the row of the Info-KSQuad table (003 Fig 8's first level of indirection;
//    the surface table is the second).
//  * "Per-KSQuad constant denominators computed once" (§3.2): computed once per non-empty span
//    and direction on the host by the tested C++ stair_constants<float> (the same float
//    arithmetic the device would do, correctly rounded divisions) and read from a storage buffer;
//    KSQuads sharing a span share its constants.
//  * Uniform mode samples the request's runs: the levels of a patch are the segment counts of
//    its u and v runs, and the evaluation stage reads the requested parameter of the vertex it is
//    given (ksquad.tese), so span-grid T gives the tessellator's (T+1)x(T+1) lattice per KSQuad
//    -- DESIGN.md's span grid -- and a regular grid gives each KSQuad the sub-grid of samples in
//    its spans. Runs past maxTessellationGenerationLevel are cut into several patches
//    (patches.h), never clamped.
//  * Capture: storage-buffer writes from the evaluation stage (vertexPipelineStoresAndAtomics),
//    rasterization discarded; transform feedback would need a vertex order the tessellator does
//    not specify.
#include "strategies/vk_ksquad/vk_ksquad.h"

#include <fmt/format.h>

#include <array>
#include <cstring>
#include <map>
#include <optional>
#include <stdexcept>
#include <tuple>

#include "reference/nurbs_math.h"
#include "strategies/cl_stair/stair_basis.h"
#include "strategies/ksquad/ksquad_table.h"
#include "strategies/vk_ksquad/patches.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"
#include "strategies/vulkan/vk_device.h"

namespace nurbs::embedded {
extern const std::string_view vk_ksquad_vert;
extern const std::string_view vk_ksquad_tesc;
extern const std::string_view vk_ksquad_tese;
}  // namespace nurbs::embedded

namespace nurbs {
namespace {

constexpr int kSurfaceInts = 12;  // ksquad_tables.glsl: SURFACE_INTS
constexpr int kPatchInts = 12;    // ksquad_tables.glsl: PATCH_INTS
constexpr int kConstantFloats = 119;
static_assert(sizeof(StairConstants<float>) == kConstantFloats * sizeof(float),
              "stair_basis.glsl reads StairConstants<float> as 119 packed floats");
constexpr int kBuffers = 6;
constexpr VkQueryPipelineStatisticFlags kStatistics =
    VK_QUERY_PIPELINE_STATISTIC_TESSELLATION_CONTROL_SHADER_PATCHES_BIT |
    VK_QUERY_PIPELINE_STATISTIC_TESSELLATION_EVALUATION_SHADER_INVOCATIONS_BIT;

vulkan::Requirements ksquad_requirements() {
  vulkan::Requirements r;
  r.tessellation_shader = true;
  r.vertex_pipeline_stores = true;
  r.pipeline_statistics = true;
  return r;
}

Capabilities ksquad_capabilities() {
  Capabilities c;
  c.max_degree = kStairMaxDegree;
  c.normals = false;
  c.fp64 = false;  // Vulkan tessellation stages in float; shaderFloat64 is optional
  c.sampling.explicit_list = false;  // not a tensor of runs
  return c;
}

class VkKsquad final : public Strategy {
 public:
  explicit VkKsquad(int device_index)
      : device_(device_index, ksquad_requirements()), queries_(device_, kStatistics) {
    record_ = device_.record();
    create_pipeline();
  }
  ~VkKsquad() override {
    vkDeviceWaitIdle(device_.handle());
    const VkDevice d = device_.handle();
    if (pipeline_) vkDestroyPipeline(d, pipeline_, nullptr);
    if (framebuffer_) vkDestroyFramebuffer(d, framebuffer_, nullptr);
    if (render_pass_) vkDestroyRenderPass(d, render_pass_, nullptr);
    if (layout_) vkDestroyPipelineLayout(d, layout_, nullptr);
    if (pool_) vkDestroyDescriptorPool(d, pool_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(d, set_layout_, nullptr);
  }

  std::string_view name() const override { return "vk-ksquad"; }
  Capabilities capabilities() const override { return ksquad_capabilities(); }
  DeviceInfo device() const override { return record_; }

  void prepare(const Scene& scene, const EvalRequest& request) override {
    refuse_unsupported(name(), capabilities(), scene, request);
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    build_tables(scene);
    upload_tables(scene);
  }

  void evaluate() override {
    device_.submit_and_wait([&](VkCommandBuffer cb) {
      queries_.reset(cb);
      queries_.begin(cb);
      VkRenderPassBeginInfo begin{};
      begin.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
      begin.renderPass = render_pass_;
      begin.framebuffer = framebuffer_;
      begin.renderArea.extent = {1, 1};
      vkCmdBeginRenderPass(cb, &begin, VK_SUBPASS_CONTENTS_INLINE);
      vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_);
      vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_, 0, 1, &set_, 0,
                              nullptr);
      vkCmdDraw(cb, static_cast<std::uint32_t>(patch_count_), 1, 0, 0);
      vkCmdEndRenderPass(cb);
      queries_.end(cb);
      VkMemoryBarrier to_host{};
      to_host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
      to_host.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
      to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
      vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TESSELLATION_EVALUATION_SHADER_BIT,
                           VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1,
                           &to_host, 0, nullptr, 0, nullptr);
    });
    evaluate_s_ = queries_.elapsed_s();
    const auto counts = queries_.statistics();
    stats_.control_patches = counts.size() > 0 ? counts[0] : 0;
    stats_.evaluation_invocations = counts.size() > 1 ? counts[1] : 0;
  }

  EvalResult read_back() override {
    std::vector<float> host(total_ * 3);
    positions_.read(host.data(), host.size() * sizeof(float));
    EvalResult out;
    std::size_t base = 0;
    for (const SurfaceSamples& s : samples_) {
      SurfaceResult r;
      r.samples = s;
      r.positions = PointArray(Precision::f32, s.count());
      std::memcpy(r.positions.f32(), host.data() + base * 3, s.count() * 3 * sizeof(float));
      base += s.count();
      out.surfaces.push_back(std::move(r));
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
  }

  DeviceTimes device_times() const override { return {evaluate_s_}; }
  const KsquadStatistics& statistics() const { return stats_; }

 private:
  static std::vector<float> homogeneous_points(const Scene& scene) {
    std::vector<float> points;
    for (const Surface& s : scene.surfaces) {
      const SurfaceNet<float> net(s);
      for (const Vec4<float>& h : net.homogeneous) points.insert(points.end(), h.begin(), h.end());
    }
    return points;
  }

  // Surface table, per-span stair constants and the Info-KSQuad table (one row per patch).
  void build_tables(const Scene& scene) {
    surfaces_.clear();
    patches_.clear();
    constants_.clear();
    params_.clear();
    std::size_t out_base = 0, point_base = 0;
    std::vector<int> param_u(scene.surfaces.size()), param_v(scene.surfaces.size());
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      const SurfaceSamples& sm = samples_[i];
      param_u[i] = static_cast<int>(params_.size());
      for (double u : sm.u) params_.push_back(static_cast<float>(u));
      param_v[i] = static_cast<int>(params_.size());
      for (double v : sm.v) params_.push_back(static_cast<float>(v));
      const int rec[kSurfaceInts] = {s.degree_u,
                                     s.degree_v,
                                     s.count_u,
                                     s.count_v,
                                     static_cast<int>(point_base),
                                     param_u[i],
                                     param_v[i],
                                     static_cast<int>(sm.v.size()),
                                     static_cast<int>(out_base),
                                     0,
                                     0,
                                     0};
      surfaces_.insert(surfaces_.end(), rec, rec + kSurfaceInts);
      point_base += s.points.size();
      out_base += sm.count();
    }
    total_ = out_base;
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
      const int offset = static_cast<int>(constants_.size());
      const float* f = reinterpret_cast<const float*>(&c);
      constants_.insert(constants_.end(), f, f + kConstantFloats);
      constant_of.emplace(key, offset);
      return offset;
    };
    const int cap = static_cast<int>(device_.limits().maxTessellationGenerationLevel);
    stats_ = {};
    stats_.level_cap = cap;
    for (const ksquad::KSQuad& q :
         ksquad::build_ksquads<float>(scene, samples_, request_.sampling)) {
      const int cu = constants(q.surface, 0, q.u.span), cv = constants(q.surface, 1, q.v.span);
      for (const ksquad::SpanRun& a : vk_ksquad::split_run(q.u, cap))
        for (const ksquad::SpanRun& b : vk_ksquad::split_run(q.v, cap)) {
          const int lu = vk_ksquad::run_level(a), lv = vk_ksquad::run_level(b);
          const int row[kPatchInts] = {q.surface, q.u.span, q.v.span, cu, cv, a.begin,
                                       a.count,   b.begin,  b.count,  lu, lv, 0};
          patches_.insert(patches_.end(), row, row + kPatchInts);
          stats_.implied_vertices += vk_ksquad::quad_domain_vertices(lu, lv);
          stats_.max_level = std::max({stats_.max_level, lu, lv});
        }
    }
    patch_count_ = patches_.size() / kPatchInts;
    stats_.patches_drawn = patch_count_;
  }

  template <typename V>
  vulkan::Buffer storage(const std::vector<V>& data, const char* what) {
    vulkan::Buffer b(device_, data.size() * sizeof(V), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, what);
    b.write(data.data(), data.size() * sizeof(V));
    return b;
  }

  void upload_tables(const Scene& scene) {
    surfaces_buf_ = storage(surfaces_, "surface table");
    patches_buf_ = storage(patches_, "Info-KSQuad table");
    constants_buf_ = storage(constants_, "stair constants");
    points_ = storage(homogeneous_points(scene), "control points");
    params_buf_ = storage(params_, "parameters");
    positions_ = vulkan::Buffer(device_, total_ * 3 * sizeof(float),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "output positions");
    const vulkan::Buffer* buffers[kBuffers] = {&surfaces_buf_, &patches_buf_, &constants_buf_,
                                               &points_,       &params_buf_,  &positions_};
    std::array<VkDescriptorBufferInfo, kBuffers> infos{};
    std::array<VkWriteDescriptorSet, kBuffers> writes{};
    for (int k = 0; k < kBuffers; ++k) {
      infos[k] = {buffers[k]->handle(), 0, VK_WHOLE_SIZE};
      writes[k] = {};
      writes[k].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
      writes[k].dstSet = set_;
      writes[k].dstBinding = static_cast<std::uint32_t>(k);
      writes[k].descriptorCount = 1;
      writes[k].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      writes[k].pBufferInfo = &infos[k];
    }
    vkUpdateDescriptorSets(device_.handle(), kBuffers, writes.data(), 0, nullptr);
  }

  // Once per strategy (STYLE.md: compiled shaders are created once, never in evaluate()).
  void create_pipeline() {
    const VkDevice d = device_.handle();
    std::array<VkDescriptorSetLayoutBinding, kBuffers> bindings{};
    for (int k = 0; k < kBuffers; ++k)
      bindings[k] = {
          static_cast<std::uint32_t>(k), VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
          VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT | VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT,
          nullptr};
    VkDescriptorSetLayoutCreateInfo set_info{};
    set_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
    set_info.bindingCount = kBuffers;
    set_info.pBindings = bindings.data();
    vulkan::check(vkCreateDescriptorSetLayout(d, &set_info, nullptr, &set_layout_),
                  "vkCreateDescriptorSetLayout");
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kBuffers};
    VkDescriptorPoolCreateInfo pool_info{};
    pool_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
    pool_info.maxSets = 1;
    pool_info.poolSizeCount = 1;
    pool_info.pPoolSizes = &size;
    vulkan::check(vkCreateDescriptorPool(d, &pool_info, nullptr, &pool_), "vkCreateDescriptorPool");
    VkDescriptorSetAllocateInfo alloc{};
    alloc.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
    alloc.descriptorPool = pool_;
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = &set_layout_;
    vulkan::check(vkAllocateDescriptorSets(d, &alloc, &set_), "vkAllocateDescriptorSets");
    VkPipelineLayoutCreateInfo layout_info{};
    layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
    layout_info.setLayoutCount = 1;
    layout_info.pSetLayouts = &set_layout_;
    vulkan::check(vkCreatePipelineLayout(d, &layout_info, nullptr, &layout_),
                  "vkCreatePipelineLayout");

    // Capture only: a render pass without attachments, rasterization discarded.
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    VkRenderPassCreateInfo rp{};
    rp.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
    rp.subpassCount = 1;
    rp.pSubpasses = &subpass;
    vulkan::check(vkCreateRenderPass(d, &rp, nullptr, &render_pass_), "vkCreateRenderPass");
    VkFramebufferCreateInfo fb{};
    fb.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
    fb.renderPass = render_pass_;
    fb.width = 1;
    fb.height = 1;
    fb.layers = 1;
    vulkan::check(vkCreateFramebuffer(d, &fb, nullptr, &framebuffer_), "vkCreateFramebuffer");

    struct Modules {
      VkDevice d;
      VkShaderModule m[3];
      ~Modules() {
        for (VkShaderModule x : m)
          if (x) vkDestroyShaderModule(d, x, nullptr);
      }
    } modules{d,
              {device_.shader_module(embedded::vk_ksquad_vert),
               device_.shader_module(embedded::vk_ksquad_tesc),
               device_.shader_module(embedded::vk_ksquad_tese)}};
    const VkShaderStageFlagBits stage_bits[3] = {VK_SHADER_STAGE_VERTEX_BIT,
                                                 VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT,
                                                 VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT};
    std::array<VkPipelineShaderStageCreateInfo, 3> stages{};
    for (int k = 0; k < 3; ++k) {
      stages[k] = {};
      stages[k].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
      stages[k].stage = stage_bits[k];
      stages[k].module = modules.m[k];
      stages[k].pName = "main";
    }
    VkPipelineVertexInputStateCreateInfo vertex_input{};
    vertex_input.sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO;
    VkPipelineInputAssemblyStateCreateInfo assembly{};
    assembly.sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO;
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_PATCH_LIST;
    VkPipelineTessellationStateCreateInfo tessellation{};
    tessellation.sType = VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO;
    tessellation.patchControlPoints = 1;
    VkPipelineRasterizationStateCreateInfo raster{};
    raster.sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO;
    raster.rasterizerDiscardEnable = VK_TRUE;
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.lineWidth = 1.0f;
    VkGraphicsPipelineCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO;
    info.stageCount = 3;
    info.pStages = stages.data();
    info.pVertexInputState = &vertex_input;
    info.pInputAssemblyState = &assembly;
    info.pTessellationState = &tessellation;
    info.pRasterizationState = &raster;
    info.layout = layout_;
    info.renderPass = render_pass_;
    vulkan::check(vkCreateGraphicsPipelines(d, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline_),
                  "vkCreateGraphicsPipelines");
  }

  vulkan::Device device_;
  vulkan::QueryPools queries_;
  DeviceInfo record_;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
  VkDescriptorSet set_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkRenderPass render_pass_ = VK_NULL_HANDLE;
  VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;

  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::vector<int> surfaces_, patches_;
  std::vector<float> constants_, params_;
  vulkan::Buffer surfaces_buf_, patches_buf_, constants_buf_, points_, params_buf_, positions_;
  std::size_t patch_count_ = 0, total_ = 0;
  std::optional<double> evaluate_s_;
  KsquadStatistics stats_;
};

}  // namespace

std::unique_ptr<Strategy> make_vk_ksquad(const StrategyOptions& options) {
  try {
    return std::make_unique<VkKsquad>(vulkan::device_option(options));
  } catch (const vulkan::MissingFeature& e) {
    throw std::runtime_error(std::string("unavailable: ") + e.what());
  }
}

KsquadStatistics ksquad_statistics(const Strategy& strategy) {
  const auto* vk = dynamic_cast<const VkKsquad*>(&strategy);
  if (!vk) throw std::invalid_argument("ksquad_statistics: not a vk-ksquad strategy");
  return vk->statistics();
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
