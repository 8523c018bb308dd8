// Direct trimming on Vulkan, shared by the Vulkan strategies: the compute pass that classifies a
// scene's tensor-grid samples (trim_classify.comp, the single-source
// strategies/trim_direct/trim_direct.h in GLSL), one dispatch per trimmed surface, float tables.
// The table buffers are public so a strategy's fragment stage can classify per fragment with the
// same code (vk-ksquad's render()).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "strategies/trim_direct/trim_tables.h"
#include "strategies/vulkan/vk_device.h"

namespace nurbs::vulkan {

class TrimClassifier {
 public:
  // The pipeline is created once (STYLE.md: never in evaluate()).
  explicit TrimClassifier(const Device& device);
  TrimClassifier(const TrimClassifier&) = delete;
  TrimClassifier& operator=(const TrimClassifier&) = delete;

  // Builds and uploads the tables of `scene` and the local parameters of its trimmed surfaces'
  // tensor samples (`samples`, one per surface).
  // Tensor samples are classified as their grids, others (explicit lists; the tessellator's own
  // span-grid parameters) sample by sample.
  void prepare(const Scene& scene, const std::vector<SurfaceSamples>& samples,
               const trim_direct::Settings& settings);
  // The same tables for other samples of the same surfaces (what a tessellator chose): only the
  // parameters and the outputs are replaced, so the tables' buffers stay bound where they are.
  void set_samples(const std::vector<SurfaceSamples>& samples);
  bool trims() const { return !launches_.empty(); }
  // Records the dispatches (and a barrier making the results visible to transfers and the host).
  void record(VkCommandBuffer cb) const;
  // The masks (empty for untrimmed surfaces), and the cost counter of the last classification.
  std::vector<std::vector<std::uint8_t>> read_masks(trim_direct::Cost& cost) const;

  const trim_direct::TrimTables<float>& tables() const { return tables_; }
  const Buffer& reals() const { return reals_; }
  const Buffer& ints() const { return ints_; }

 private:
  struct Launch {
    std::int32_t base, u_offset, nu, v_offset, nv, out_base;
    float epsilon;
    std::int32_t iterations;
    std::int32_t paired;  // 1: sample k is (u[k], v[k]) (nv = 1); 0: the nu x nv grid
  };
  const Device& device_;
  std::unique_ptr<StorageSet> set_;
  std::unique_ptr<ComputePipeline> pipeline_;
  trim_direct::TrimTables<float> tables_;
  Buffer reals_, ints_, coords_, inside_, reads_;
  std::vector<Launch> launches_;
  std::vector<std::size_t> surface_of_launch_;
  std::size_t surfaces_ = 0, total_ = 0;
  std::int32_t iterations_ = 0;
};

}  // namespace nurbs::vulkan
