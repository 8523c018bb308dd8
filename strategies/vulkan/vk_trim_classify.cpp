#include "strategies/vulkan/vk_trim_classify.h"

#include <memory>
#include <vector>

namespace nurbs::embedded {
extern const std::string_view vk_trim_classify_comp;
}  // namespace nurbs::embedded

namespace nurbs::vulkan {

namespace {
constexpr std::uint32_t kBindings = 5;  // trim_classify.comp
constexpr std::uint32_t kGroupSize = 64;
}  // namespace

TrimClassifier::TrimClassifier(const Device& device) : device_(device) {
  set_ = std::make_unique<StorageSet>(
      device_, std::vector<VkShaderStageFlags>(kBindings, VK_SHADER_STAGE_COMPUTE_BIT));
  pipeline_ = std::make_unique<ComputePipeline>(
      device_, *set_, sizeof(Launch), embedded::vk_trim_classify_comp, "trim_classify.comp");
}

void TrimClassifier::prepare(const Scene& scene, const std::vector<SurfaceSamples>& samples,
                             const trim_direct::Settings& settings) {
  tables_ = trim_direct::build_tables<float>(scene, settings);
  surfaces_ = scene.surfaces.size();
  iterations_ = settings.iterations;
  const auto storage = [&](const auto& data, const char* what) {
    Buffer b(device_, data.size() * sizeof(data[0]), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, what);
    if (!data.empty()) b.write(data.data(), data.size() * sizeof(data[0]));
    return b;
  };
  reals_ = storage(tables_.reals, "trim tables (reals)");
  ints_ = storage(tables_.ints, "trim tables (ints)");
  set_samples(samples);
}

void TrimClassifier::set_samples(const std::vector<SurfaceSamples>& samples) {
  launches_.clear();
  surface_of_launch_.clear();
  std::vector<float> coords;
  std::size_t out = 0;
  for (std::size_t i = 0; i < surfaces_; ++i) {
    const auto& st = tables_.surfaces[i];
    if (st.base < 0) continue;
    const SurfaceSamples& sm = samples[i];
    Launch l{};
    l.base = st.base;
    l.u_offset = static_cast<std::int32_t>(coords.size());
    for (double u : sm.u) coords.push_back(trim_direct::local_u<float>(st, u));
    l.v_offset = static_cast<std::int32_t>(coords.size());
    for (double v : sm.v) coords.push_back(trim_direct::local_v<float>(st, v));
    l.paired = sm.tensor ? 0 : 1;
    l.nu = static_cast<std::int32_t>(sm.tensor ? sm.u.size() : sm.count());
    l.nv = static_cast<std::int32_t>(sm.tensor ? sm.v.size() : 1);
    l.out_base = static_cast<std::int32_t>(out);
    l.epsilon = st.epsilon;
    l.iterations = iterations_;
    out += sm.count();
    launches_.push_back(l);
    surface_of_launch_.push_back(i);
  }
  total_ = out;
  coords_ = Buffer(device_, std::max<std::size_t>(coords.size(), 1) * sizeof(float),
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "trim local parameters");
  if (!coords.empty()) coords_.write(coords.data(), coords.size() * sizeof(float));
  inside_ = Buffer(device_, total_ * sizeof(std::uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                   "trim mask");
  reads_ = Buffer(device_, total_ * sizeof(std::int32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                  "trim cost counter");
  set_->write({&reals_, &ints_, &coords_, &inside_, &reads_});
}

void TrimClassifier::record(VkCommandBuffer cb) const {
  if (launches_.empty()) return;
  pipeline_->bind(cb, *set_);
  for (const Launch& l : launches_) {
    const std::uint32_t count = static_cast<std::uint32_t>(l.nu) * static_cast<std::uint32_t>(l.nv);
    if (count == 0) continue;
    vkCmdPushConstants(cb, pipeline_->layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof l, &l);
    vkCmdDispatch(cb, (count + kGroupSize - 1) / kGroupSize, 1, 1);
  }
  VkMemoryBarrier to_host{};
  to_host.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER;
  to_host.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  to_host.dstAccessMask = VK_ACCESS_HOST_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
  vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &to_host,
                       0, nullptr, 0, nullptr);
}

std::vector<std::vector<std::uint8_t>> TrimClassifier::read_masks(trim_direct::Cost& cost) const {
  std::vector<std::vector<std::uint8_t>> masks(surfaces_);
  if (total_ == 0) return masks;
  std::vector<std::uint32_t> inside(total_);
  std::vector<std::int32_t> reads(total_);
  inside_.read(inside.data(), total_ * sizeof(std::uint32_t));
  reads_.read(reads.data(), total_ * sizeof(std::int32_t));
  cost = {};
  for (std::int32_t r : reads) cost.add(2 * r);
  for (std::size_t k = 0; k < launches_.size(); ++k) {
    const Launch& l = launches_[k];
    const std::size_t count = static_cast<std::size_t>(l.nu) * static_cast<std::size_t>(l.nv);
    masks[surface_of_launch_[k]].assign(inside.begin() + l.out_base,
                                        inside.begin() + l.out_base + static_cast<long>(count));
  }
  return masks;
}

}  // namespace nurbs::vulkan
