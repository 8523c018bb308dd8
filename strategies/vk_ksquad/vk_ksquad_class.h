// vk-ksquad's strategy class (003 §2-4), shared by the files of its mappings: vk_ksquad.cpp holds
// what every mapping uses (tables, pipelines, capture, render, the options), uniform_mapping.cpp,
// adaptive_mapping.cpp, gs_mapping.cpp and nonuniform_mapping.cpp each mapping's own members
// beside its host pieces. Private to strategies/vk_ksquad; tests use vk_ksquad_strategy.h.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "strategies/strategy.h"
#include "strategies/trim_direct/trim_tables.h"
#include "strategies/vk_ksquad/adaptive_mapping.h"
#include "strategies/vk_ksquad/ksquad_layout.h"
#include "strategies/vk_ksquad/ksquad_pipeline.h"
#include "strategies/vk_ksquad/ksquad_settings.h"
#include "strategies/vk_ksquad/patches.h"
#include "strategies/vk_ksquad/vk_ksquad_strategy.h"
#include "strategies/vulkan/vk_device.h"
#include "strategies/vulkan/vk_trim_classify.h"

namespace nurbs::vk_ksquad {

class VkKsquad final : public Strategy {
 public:
  VkKsquad(int device_index, const KsquadSettings& settings, const trim_direct::Settings& trim);
  ~VkKsquad() override {
    vkDeviceWaitIdle(device_.handle());
    const VkDevice d = device_.handle();
    for (const auto& pipelines : {capture_pipelines_, raster_pipelines_})
      for (const auto& [degrees, pipeline] : pipelines) vkDestroyPipeline(d, pipeline, nullptr);
    if (layout_) vkDestroyPipelineLayout(d, layout_, nullptr);
  }

  std::string_view name() const override { return "vk-ksquad"; }
  Capabilities capabilities() const override;
  DeviceInfo device() const override { return record_; }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override;

  bool classify() override;

  void evaluate() override;

  EvalResult read_back() override;
  void read_back_into(EvalResult& out) override;

  void read_back_uniform(EvalResult& out);

  void update_control_points(const Scene& scene) override;

  DeviceTimes device_times() const override { return times_; }

  bool render() override;

  std::size_t rendered_pixels() const;

  std::optional<RenderedImage> last_render() override { return read_image(); }
  std::optional<RenderedImage> read_image() const;

  KsquadStatistics statistics() const;

  std::vector<KsdieRecord> ksdice() const;

  std::vector<float> read_levels() const;

  std::vector<PatchLevels> patch_levels() const;

  std::vector<CapturedEdge> captured_edges() const;

 private:
  // Each mapping's own pieces (uniform_mapping.cpp, adaptive_mapping.cpp, gs_mapping.cpp,
  // nonuniform_mapping.cpp); the rest of the class is what they share: tables, pipelines, capture,
  // render.
  void check_gs_limits() const;
  void refuse_gs(const EvalRequest& request) const;
  void check_nonuniform_limits() const;
  bool span_grid_samples() const;

  static std::vector<float> homogeneous_points(const Scene& scene);

  std::vector<std::int32_t> trim_surface_rows() const;

  std::vector<float> read_slots() const;

  EvalResult read_back_nonuniform();

  EvalResult read_back_adaptive();
  void record_eq3_details(const KsquadStatistics& st);

  void set_mode(const Scene& scene);

  void build_tables(const Scene& scene);

  template <typename V>
  vulkan::Buffer storage(const std::vector<V>& data, const char* what) {
    vulkan::Buffer b(device_, data.size() * sizeof(V), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, what);
    b.write(data.data(), data.size() * sizeof(V));
    return b;
  }

  void upload_tables(const Scene& scene);

  void create_pipeline();
  void compute_constants();

  using Pipelines = vk_ksquad::Pipelines;

  VkPipeline pipeline_for(Pipelines& pipelines, bool raster, const Draw& draw);

  void record_corners(VkCommandBuffer cb) const;

  void record_draws(VkCommandBuffer cb, const Pipelines& pipelines,
                    const std::vector<Draw>& draws) const {
    vk_ksquad::record_draws(cb, layout_, *set_, pipelines, draws, mode_, draw_stages());
  }

  VkShaderStageFlags draw_stages() const;
  VkPipelineStageFlags writing_stages() const;
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
  // vk-constants=device: the knot vectors (floats), 4 ints per (surface, direction, span) job,
  // and the constants pass (ksquad_constants.comp) with its own descriptor set.
  std::vector<float> knot_table_;
  std::vector<int> constant_jobs_;
  vulkan::Buffer knots_buf_, constant_jobs_buf_;
  std::unique_ptr<vulkan::StorageSet> constants_set_;
  std::unique_ptr<vulkan::ComputePipeline> constants_pass_;
  std::size_t patch_count_ = 0, total_ = 0, surface_count_ = 0, region_ = 0;
  KsquadSettings settings_;
  ModeConstants mode_{};
  vk_ksquad::Corners corner_table_;
  DeviceTimes times_;  // the phases' last device times (device_times())
  KsquadStatistics stats_;
};

}  // namespace nurbs::vk_ksquad
