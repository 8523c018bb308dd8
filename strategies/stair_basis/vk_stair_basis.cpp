#include "strategies/stair_basis/vk_stair_basis.h"

#include <cstdint>

#include "strategies/vulkan/vk_device.h"

namespace nurbs::embedded {
extern const std::string_view vk_stair_basis_comp;
}  // namespace nurbs::embedded

namespace nurbs::vulkan {

std::vector<float> stair_basis_on_vulkan(const std::vector<float>& constants,
                                         const std::vector<StairJob>& jobs, int device_index) {
  constexpr std::uint32_t kGroupSize = 64;  // stair_basis.comp
  const Device device(device_index, Requirements{});
  const StorageSet set(device, std::vector<VkShaderStageFlags>(4, VK_SHADER_STAGE_COMPUTE_BIT));
  std::vector<int> ints;
  std::vector<float> params;
  for (const StairJob& j : jobs) {
    ints.insert(ints.end(), {j.constants, j.degree, j.derivative ? 1 : 0});
    params.push_back(j.u);
  }
  const std::size_t out_count = jobs.size() * (kStairMaxDegree + 1);
  const VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  Buffer c(device, constants.size() * sizeof(float) + 4, usage, "stair constants");
  Buffer i(device, ints.size() * sizeof(int) + 4, usage, "jobs");
  Buffer p(device, params.size() * sizeof(float) + 4, usage, "parameters");
  Buffer o(device, out_count * sizeof(float) + 4, usage, "values");
  c.write(constants.data(), constants.size() * sizeof(float));
  i.write(ints.data(), ints.size() * sizeof(int));
  p.write(params.data(), params.size() * sizeof(float));
  set.write({&c, &i, &p, &o});

  const std::int32_t count = static_cast<std::int32_t>(jobs.size());
  const ComputePipeline pipeline(device, set, sizeof count, embedded::vk_stair_basis_comp,
                                 "stair_basis.comp");
  device.submit_and_wait([&](VkCommandBuffer cb) {
    pipeline.bind(cb, set);
    vkCmdPushConstants(cb, pipeline.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof count, &count);
    vkCmdDispatch(cb, (static_cast<std::uint32_t>(count) + kGroupSize - 1) / kGroupSize, 1, 1);
  });
  std::vector<float> out(out_count);
  o.read(out.data(), out.size() * sizeof(float));
  return out;
}

}  // namespace nurbs::vulkan
