#include "strategies/vk_ksquad/ksquad_pipeline.h"

#include <array>
#include <cstring>
#include <string_view>
#include <vector>

#include "strategies/host_results.h"
#include "strategies/vk_ksquad/uniform_mapping.h"

namespace nurbs::embedded {
extern const std::string_view vk_ksquad_vert;
extern const std::string_view vk_ksquad_tesc;
extern const std::string_view vk_ksquad_tese;
extern const std::string_view vk_ksquad_geom;
extern const std::string_view vk_ksquad_frag;
extern const std::string_view vk_ksquad_nonuniform_tese;
extern const std::string_view vk_ksquad_nonuniform_geom;
}  // namespace nurbs::embedded

namespace nurbs::vk_ksquad {

PipelineShaders ksquad_shaders(Mapping mapping) {
  if (mapping == Mapping::nonuniform)
    return {embedded::vk_ksquad_vert, embedded::vk_ksquad_tesc, embedded::vk_ksquad_nonuniform_tese,
            embedded::vk_ksquad_nonuniform_geom, embedded::vk_ksquad_frag};
  return {embedded::vk_ksquad_vert, embedded::vk_ksquad_tesc, embedded::vk_ksquad_tese,
          embedded::vk_ksquad_geom, embedded::vk_ksquad_frag};
}

Stages mapping_stages(Mapping mapping) {
  switch (mapping) {
    case Mapping::gs:
      return Stages::geometry;
    case Mapping::nonuniform:
      return Stages::tessellation_geometry;
    case Mapping::uniform:
    case Mapping::adaptive:
      break;
  }
  return Stages::tessellation;
}

VkPipeline make_pipeline(const vulkan::Device& device, const PipelineShaders& shaders,
                         VkPipelineLayout layout, bool raster, Stages which, VkRenderPass pass,
                         int du, int dv, std::uint32_t width, std::uint32_t height) {
  const bool geometry = which == Stages::geometry;
  const VkDevice d = device.handle();
  struct Modules {
    VkDevice d;
    std::vector<VkShaderModule> m;
    ~Modules() {
      for (VkShaderModule x : m) vkDestroyShaderModule(d, x, nullptr);
    }
  } modules{d, {}};
  std::vector<VkShaderStageFlagBits> stage_bits;
  const auto add = [&](VkShaderStageFlagBits bit, std::string_view spirv) {
    modules.m.push_back(device.shader_module(spirv));
    stage_bits.push_back(bit);
  };
  add(VK_SHADER_STAGE_VERTEX_BIT, shaders.vert);
  if (!geometry) {
    add(VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT, shaders.tesc);
    add(VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT, shaders.tese);
  }
  if (which != Stages::tessellation) add(VK_SHADER_STAGE_GEOMETRY_BIT, shaders.geom);
  if (raster) add(VK_SHADER_STAGE_FRAGMENT_BIT, shaders.frag);
  // ksquad.tese, ksquad.geom: kRaster, kDegreeU, kDegreeV; ksquad.tesc: kRaster
  const std::int32_t constants[3] = {raster ? 1 : 0, du, dv};
  const VkSpecializationMapEntry entries[3] = {{0, 0, 4}, {1, 4, 4}, {2, 8, 4}};
  VkSpecializationInfo specialization{};
  specialization.mapEntryCount = 3;
  specialization.pMapEntries = entries;
  specialization.dataSize = sizeof constants;
  specialization.pData = constants;
  std::vector<VkPipelineShaderStageCreateInfo> stages(stage_bits.size());
  for (std::size_t k = 0; k < stages.size(); ++k) {
    stages[k].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[k].stage = stage_bits[k];
    stages[k].module = modules.m[k];
    stages[k].pName = "main";
    if (stage_bits[k] != VK_SHADER_STAGE_VERTEX_BIT &&
        stage_bits[k] != VK_SHADER_STAGE_FRAGMENT_BIT)
      stages[k].pSpecializationInfo = &specialization;
  }
  VkPipelineVertexInputStateCreateInfo vertex_input{};
  vertex_input.sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO;
  VkPipelineInputAssemblyStateCreateInfo assembly{};
  assembly.sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO;
  assembly.topology =
      geometry ? VK_PRIMITIVE_TOPOLOGY_POINT_LIST : VK_PRIMITIVE_TOPOLOGY_PATCH_LIST;
  VkPipelineTessellationStateCreateInfo tessellation{};
  tessellation.sType = VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO;
  tessellation.patchControlPoints = 1;
  VkPipelineRasterizationStateCreateInfo rasterization{};
  rasterization.sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO;
  rasterization.rasterizerDiscardEnable = raster ? VK_FALSE : VK_TRUE;
  rasterization.polygonMode = VK_POLYGON_MODE_FILL;
  rasterization.cullMode = VK_CULL_MODE_NONE;
  rasterization.lineWidth = 1.0f;
  const VkViewport viewport{0, 0, static_cast<float>(width), static_cast<float>(height), 0, 1};
  const VkRect2D scissor{{0, 0}, {width, height}};
  VkPipelineViewportStateCreateInfo viewport_state{};
  viewport_state.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO;
  viewport_state.viewportCount = 1;
  viewport_state.pViewports = &viewport;
  viewport_state.scissorCount = 1;
  viewport_state.pScissors = &scissor;
  VkPipelineMultisampleStateCreateInfo multisample{};
  multisample.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO;
  multisample.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo depth{};
  depth.sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO;
  depth.depthTestEnable = VK_TRUE;
  depth.depthWriteEnable = VK_TRUE;
  depth.depthCompareOp = VK_COMPARE_OP_LESS;
  VkPipelineColorBlendAttachmentState blend_attachment{};
  blend_attachment.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                    VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  VkPipelineColorBlendStateCreateInfo blend{};
  blend.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO;
  blend.attachmentCount = 1;
  blend.pAttachments = &blend_attachment;
  VkGraphicsPipelineCreateInfo info{};
  info.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO;
  info.stageCount = static_cast<std::uint32_t>(stages.size());
  info.pStages = stages.data();
  info.pVertexInputState = &vertex_input;
  info.pInputAssemblyState = &assembly;
  info.pTessellationState = geometry ? nullptr : &tessellation;
  info.pRasterizationState = &rasterization;
  if (raster) {
    info.pViewportState = &viewport_state;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
  }
  info.layout = layout;
  info.renderPass = pass;
  VkPipeline pipeline = VK_NULL_HANDLE;
  vulkan::check(vkCreateGraphicsPipelines(d, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline),
                "vkCreateGraphicsPipelines");
  return pipeline;
}

VkPipelineLayout make_layout(const vulkan::Device& device, const vulkan::StorageSet& set,
                             VkShaderStageFlags push_stages) {
  VkPipelineLayoutCreateInfo layout_info{};
  layout_info.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  layout_info.setLayoutCount = 1;
  layout_info.pSetLayouts = &set.layout();
  const VkPushConstantRange push{push_stages, 0, sizeof(ModeConstants)};
  layout_info.pushConstantRangeCount = 1;
  layout_info.pPushConstantRanges = &push;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  vulkan::check(vkCreatePipelineLayout(device.handle(), &layout_info, nullptr, &layout),
                "vkCreatePipelineLayout");
  return layout;
}

void record_draws(VkCommandBuffer cb, VkPipelineLayout layout, const vulkan::StorageSet& set,
                  const Pipelines& pipelines, const std::vector<Draw>& draws,
                  const ModeConstants& mode, VkShaderStageFlags push_stages) {
  vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, layout, 0, 1, &set.handle(), 0,
                          nullptr);
  for (const Draw& draw : draws) {
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipelines.at({draw.du, draw.dv}));
    ModeConstants m = mode;
    m.patch_base = static_cast<std::int32_t>(draw.first);
    vkCmdPushConstants(cb, layout, push_stages, 0, sizeof m, &m);
    vkCmdDraw(cb, draw.count, 1, 0, 0);
  }
}

CaptureTarget::CaptureTarget(const vulkan::Device& device) : device_(device) {
  const VkDevice d = device_.handle();
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  VkRenderPassCreateInfo rp{};
  rp.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
  rp.subpassCount = 1;
  rp.pSubpasses = &subpass;
  vulkan::check(vkCreateRenderPass(d, &rp, nullptr, &pass_), "vkCreateRenderPass");
  VkFramebufferCreateInfo fb{};
  fb.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
  fb.renderPass = pass_;
  fb.width = 1;
  fb.height = 1;
  fb.layers = 1;
  if (const VkResult r = vkCreateFramebuffer(d, &fb, nullptr, &framebuffer_); r != VK_SUCCESS) {
    vkDestroyRenderPass(d, pass_, nullptr);
    vulkan::check(r, "vkCreateFramebuffer");
  }
}

CaptureTarget::~CaptureTarget() {
  const VkDevice d = device_.handle();
  if (framebuffer_) vkDestroyFramebuffer(d, framebuffer_, nullptr);
  if (pass_) vkDestroyRenderPass(d, pass_, nullptr);
}

void CaptureTarget::begin(VkCommandBuffer cb) const {
  VkRenderPassBeginInfo begin{};
  begin.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
  begin.renderPass = pass_;
  begin.framebuffer = framebuffer_;
  begin.renderArea.extent = {1, 1};
  vkCmdBeginRenderPass(cb, &begin, VK_SUBPASS_CONTENTS_INLINE);
}

RasterTarget::RasterTarget(const vulkan::Device& device, std::uint32_t width, std::uint32_t height)
    : device_(device), width_(width), height_(height) {
  const VkDevice d = device_.handle();
  color_ = std::make_unique<vulkan::Image>(
      device_, kColorFormat, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
      VK_IMAGE_ASPECT_COLOR_BIT, width_, height_);
  depth_ = std::make_unique<vulkan::Image>(device_, VK_FORMAT_D32_SFLOAT,
                                           VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                           VK_IMAGE_ASPECT_DEPTH_BIT, width_, height_);
  VkAttachmentDescription attachments[2] = {};
  attachments[0].format = kColorFormat;
  attachments[0].samples = VK_SAMPLE_COUNT_1_BIT;
  attachments[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
  attachments[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
  attachments[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
  attachments[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
  attachments[0].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  attachments[1] = attachments[0];
  attachments[1].format = VK_FORMAT_D32_SFLOAT;
  attachments[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
  attachments[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
  const VkAttachmentReference color_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  const VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription subpass{};
  subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  subpass.colorAttachmentCount = 1;
  subpass.pColorAttachments = &color_ref;
  subpass.pDepthStencilAttachment = &depth_ref;
  VkRenderPassCreateInfo rp{};
  rp.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
  rp.attachmentCount = 2;
  rp.pAttachments = attachments;
  rp.subpassCount = 1;
  rp.pSubpasses = &subpass;
  vulkan::check(vkCreateRenderPass(d, &rp, nullptr, &pass_), "vkCreateRenderPass");
  const VkImageView views[2] = {color_->view(), depth_->view()};
  VkFramebufferCreateInfo fb{};
  fb.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
  fb.renderPass = pass_;
  fb.attachmentCount = 2;
  fb.pAttachments = views;
  fb.width = width_;
  fb.height = height_;
  fb.layers = 1;
  vulkan::check(vkCreateFramebuffer(d, &fb, nullptr, &framebuffer_), "vkCreateFramebuffer");
}

RasterTarget::~RasterTarget() {
  const VkDevice d = device_.handle();
  if (framebuffer_) vkDestroyFramebuffer(d, framebuffer_, nullptr);
  if (pass_) vkDestroyRenderPass(d, pass_, nullptr);
}

RenderedImage RasterTarget::read() const {
  const std::size_t pixels = std::size_t{width_} * height_;
  vulkan::Buffer staging(device_, pixels * 4, 0, "rendered image");
  device_.submit_and_wait([&](VkCommandBuffer cb) {
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {width_, height_, 1};
    vkCmdCopyImageToBuffer(cb, color_->handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                           staging.handle(), 1, &region);
  });
  RenderedImage image;
  image.width = static_cast<int>(width_);
  image.height = static_cast<int>(height_);
  image.rgba.resize(pixels * 4);
  staging.read(image.rgba.data(), pixels * 4);
  return image;
}

void read_uniform_capture(EvalResult& out, const std::vector<SurfaceSamples>& samples,
                          const vulkan::Buffer& positions, const vulkan::Buffer* params,
                          const vulkan::Buffer* normals) {
  const std::size_t total = total_samples(samples);
  if (total == 0) {
    shape_results(out, samples, Precision::f32, normals != nullptr);
    return;
  }
  // Each view is scattered before the next is taken: the device's staging buffer holds one.
  const std::size_t bytes = total * 3 * sizeof(float);
  shape_results(out, samples, Precision::f32, normals != nullptr);
  scatter_into(out, &SurfaceResult::positions,
               static_cast<const float*>(positions.host_view(bytes)));
  if (params) {
    const auto* uv = static_cast<const float*>(params->host_view(total * 2 * sizeof(float)));
    std::size_t base = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      out.surfaces[i].samples = chosen_samples(samples[i], uv + 2 * base);
      base += samples[i].count();
    }
  }
  if (normals)
    scatter_into(out, &SurfaceResult::normals,
                 static_cast<const float*>(normals->host_view(bytes)));
}

}  // namespace nurbs::vk_ksquad
