// The Vulkan pieces every vk-ksquad mapping draws with (and vk-bezier, the same pipeline with its
// own evaluation stage): the graphics pipelines (capture: the evaluation stage stores,
// rasterization discarded; raster: render()'s image), their layout and draws, the capture pass
// and render()'s offscreen target.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <map>
#include <memory>
#include <string_view>
#include <utility>
#include <vector>

#include "strategies/strategy.h"
#include "strategies/vk_ksquad/ksquad_layout.h"
#include "strategies/vk_ksquad/ksquad_settings.h"
#include "strategies/vk_ksquad/patches.h"
#include "strategies/vulkan/vk_device.h"

namespace nurbs::vk_ksquad {

inline constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

// The embedded SPIR-V of a pipeline's stages (empty: a stage the pipeline never uses).
struct PipelineShaders {
  std::string_view vert, tesc, tese, geom, frag;
};
// vk-ksquad's (ksquad.vert, .tesc, .tese, .geom, .frag); `nonuniform`: the nonuniform mapping's
// evaluation and geometry stages (ksquad_nonuniform.tese, .geom) instead. vk-bezier draws with its
// vertex and control stages and its own evaluation stage.
PipelineShaders ksquad_shaders(Mapping mapping = Mapping::uniform);

// The stages between the vertex and fragment stages: the tessellator's (uniform, adaptive), the
// GS mapping's geometry stage alone (ksquad.geom), or both (nonuniform).
enum class Stages { tessellation, geometry, tessellation_geometry };
// uniform, adaptive: tessellation; gs: geometry; nonuniform: tessellation_geometry.
Stages mapping_stages(Mapping mapping);

// Capture (rasterization discarded) or raster (the evaluation stage's kRaster = 1, a fragment
// stage, depth test, a width x height viewport); the degrees are the evaluation stage's
// specialization constants (0: read from the surface table).
VkPipeline make_pipeline(const vulkan::Device& device, const PipelineShaders& shaders,
                         VkPipelineLayout layout, bool raster, Stages stages, VkRenderPass pass,
                         int du, int dv, std::uint32_t width, std::uint32_t height);

// The pipeline layout: `set` and ModeConstants as push constants to `push_stages`.
VkPipelineLayout make_layout(const vulkan::Device& device, const vulkan::StorageSet& set,
                             VkShaderStageFlags push_stages);

// Pipelines by degree pair (created once per pair, kept).
using Pipelines = std::map<std::pair<int, int>, VkPipeline>;

// Binds `set` and, per draw, its degree pair's pipeline and `mode` with the draw's first row as
// patch_base; one patch (one vertex) per row.
void record_draws(VkCommandBuffer cb, VkPipelineLayout layout, const vulkan::StorageSet& set,
                  const Pipelines& pipelines, const std::vector<Draw>& draws,
                  const ModeConstants& mode, VkShaderStageFlags push_stages);

// Capture only: a render pass without attachments and its 1x1 framebuffer (rasterization is
// discarded, the evaluation stage's stores are the output).
class CaptureTarget {
 public:
  explicit CaptureTarget(const vulkan::Device& device);
  ~CaptureTarget();
  CaptureTarget(const CaptureTarget&) = delete;
  CaptureTarget& operator=(const CaptureTarget&) = delete;
  VkRenderPass pass() const { return pass_; }
  // Begins the pass on `cb`.
  void begin(VkCommandBuffer cb) const;

 private:
  const vulkan::Device& device_;
  VkRenderPass pass_ = VK_NULL_HANDLE;
  VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
};

// The render target of render(): RGBA8 colour (copied out by tests), 32-bit depth, a render
// pass clearing both.
class RasterTarget {
 public:
  RasterTarget(const vulkan::Device& device, std::uint32_t width, std::uint32_t height);
  ~RasterTarget();
  RasterTarget(const RasterTarget&) = delete;
  RasterTarget& operator=(const RasterTarget&) = delete;
  VkRenderPass pass() const { return pass_; }
  VkFramebuffer framebuffer() const { return framebuffer_; }
  // The colour image of the last pass. Row 0 of a Vulkan framebuffer is its top row, so the rows
  // are top to bottom.
  RenderedImage read() const;

 private:
  const vulkan::Device& device_;
  std::uint32_t width_, height_;
  std::unique_ptr<vulkan::Image> color_, depth_;
  VkRenderPass pass_ = VK_NULL_HANDLE;
  VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
};

// A uniform capture read back (vk-ksquad's uniform mapping, vk-bezier) into `out`, keeping its
// storage (strategies/host_results.h): per surface its samples (a span grid's as the tessellator
// placed them, from `params`; the requested ones when `params` is null), its positions and, when
// `normals` is given, its normals; `samples` in output order.
void read_uniform_capture(EvalResult& out, const std::vector<SurfaceSamples>& samples,
                          const vulkan::Buffer& positions, const vulkan::Buffer* params,
                          const vulkan::Buffer* normals);

}  // namespace nurbs::vk_ksquad
