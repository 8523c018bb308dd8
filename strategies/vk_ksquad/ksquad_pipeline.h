// The Vulkan pieces every vk-ksquad mapping draws with: its graphics pipelines (capture: the
// evaluation stage stores, rasterization discarded; raster: render()'s image) and render()'s
// offscreen target.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>

#include "strategies/strategy.h"
#include "strategies/vulkan/vk_device.h"

namespace nurbs::vk_ksquad {

inline constexpr VkFormat kColorFormat = VK_FORMAT_R8G8B8A8_UNORM;

// Capture (rasterization discarded) or raster (the evaluation stage's kRaster = 1, a fragment
// stage, depth test, a width x height viewport); the degrees are the evaluation stage's
// specialization constants (0: read from the surface table). `geometry`: the GS mapping's
// vertex + geometry stages (ksquad.geom) instead of the tessellation stages.
VkPipeline make_pipeline(const vulkan::Device& device, VkPipelineLayout layout, bool raster,
                         bool geometry, VkRenderPass pass, int du, int dv, std::uint32_t width,
                         std::uint32_t height);

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

}  // namespace nurbs::vk_ksquad
