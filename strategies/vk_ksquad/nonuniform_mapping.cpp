#include "strategies/vk_ksquad/nonuniform_mapping.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "reference/nurbs_math.h"
#include "strategies/vk_ksquad/adaptive_mapping.h"
#include "strategies/vk_ksquad/vk_ksquad_class.h"

namespace nurbs::vk_ksquad {

namespace {

struct Side {
  std::array<Vec3<double>, kFriendSamples> points, normals;
};

// Side e of surface s sampled at kFriendSamples equally spaced parameters.
Side sample_side(const Surface& s, int e) {
  const SurfaceNet<double> net(s);
  Side out;
  for (int k = 0; k < kFriendSamples; ++k) {
    const double t = static_cast<double>(k) / (kFriendSamples - 1);
    const double u = e == 0   ? s.u_min()
                     : e == 2 ? s.u_max()
                              : s.u_min() + t * (s.u_max() - s.u_min());
    const double v = e == 1   ? s.v_min()
                     : e == 3 ? s.v_max()
                              : s.v_min() + t * (s.v_max() - s.v_min());
    out.points[k] = surface_point(net, u, v);
    out.normals[k] = surface_normal(net, u, v);
  }
  return out;
}

double distance(const Vec3<double>& a, const Vec3<double>& b) {
  return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                   (a[2] - b[2]) * (a[2] - b[2]));
}

}  // namespace

std::vector<int> friendless_sides(const Scene& scene) {
  const double tolerance = kFriendDistance * scene.bounding_box_diagonal();
  const double sin_angle = std::sin(kFriendAngleDeg * M_PI / 180);
  std::vector<std::array<Side, 4>> sides(scene.surfaces.size());
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
    for (int e = 0; e < 4; ++e) sides[i][e] = sample_side(scene.surfaces[i], e);
  std::vector<int> mask(scene.surfaces.size(), 0);
  for (std::size_t i = 0; i < sides.size(); ++i)
    for (int e = 0; e < 4; ++e)
      for (std::size_t j = 0; j < sides.size(); ++j)
        for (int f = 0; f < 4; ++f) {
          if (i == j) continue;
          const Side &a = sides[i][e], &b = sides[j][f];
          for (const bool reversed : {false, true}) {
            const auto partner = [&](int k) { return reversed ? kFriendSamples - 1 - k : k; };
            bool shared = true, g1 = true;
            for (int k = 0; k < kFriendSamples && shared; ++k) {
              shared = distance(a.points[k], b.points[partner(k)]) <= tolerance;
              const Vec3<double>&n = a.normals[k], &m = b.normals[partner(k)];
              // unit or zero (a collapsed side): only defined normals are compared
              if (norm(n) > 0.5 && norm(m) > 0.5 && !(norm(cross(n, m)) <= sin_angle)) g1 = false;
            }
            if (shared && !g1) mask[i] |= 1 << e;
          }
        }
  return mask;
}

std::vector<KsdieRecord> nonuniform_records(const HostTables& tables,
                                            const std::vector<float>& levels,
                                            const std::vector<int>& ksdice, int max_level) {
  std::vector<KsdieRecord> out;
  for (std::size_t k = 0; k < tables.patch_count(); ++k) {
    const int* row = &tables.patches[kPatchInts * k];
    // ksquad.tesc stores the set outer levels (level_v, level_u, level_v, level_u)
    const int level_u = static_cast<int>(levels[8 * k + 1]);
    const int level_v = static_cast<int>(levels[8 * k]);
    for (int i = 0; i < level_u; ++i)
      for (int j = 0; j < level_v; ++j) {
        const int* r = &ksdice[kNuKsdieInts * ((k * max_level + i) * max_level + j)];
        out.push_back({row[0], row[1], row[2], i, j, level_u, level_v, r[0], r[1], r[2], r[3]});
      }
  }
  return out;
}

KsquadStatistics nonuniform_statistics(KsquadStatistics st,
                                       const std::vector<KsdieRecord>& records) {
  st.ksdice = st.subdivided_linear = st.subdivided_boundary = 0;
  st.culled_frustum = st.culled_back = st.triangles = 0;
  for (const KsdieRecord& r : records) {
    st.ksdice += r.status != 0;
    st.culled_frustum += r.status == kKsdieFrustumCulled;
    st.culled_back += r.status == kKsdieBackCulled;
    if (r.status != kKsdieEmitted) continue;
    st.subdivided_linear += r.depth_linear > 0;
    st.subdivided_boundary += r.depth_boundary > 0;
    const int depth = std::max(r.depth_linear, r.depth_boundary);
    st.triangles += 2ull << (2 * depth);  // 2 per sub-KSDie, 4^depth of them
  }
  return st;
}

EvalResult nonuniform_result(const HostTables& tables, const std::vector<float>& slots,
                             bool normals, int max_level, std::size_t surface_count) {
  CapturedSamples out(surface_count, normals);
  const std::size_t per_patch = ksdie_slots(max_level) * kNuLattice * kNuLattice;
  for (std::size_t k = 0; k < tables.patch_count(); ++k) {
    const int surface = tables.patches[kPatchInts * k];
    for (std::size_t j = 0; j < per_patch; ++j) {
      const float* slot = &slots[kNuVertexFloats * (k * per_patch + j)];
      if (!std::isnan(slot[0])) out.add(surface, slot, normals ? slot + 5 : nullptr);
    }
  }
  return out.result();
}

// VkKsquad's nonuniform mapping: the geometry stage's output limit, records and emitted vertices.

// ksquad_nonuniform.geom: max_vertices, 2^kNuDepth strips of 2 (2^kNuDepth + 1)
constexpr std::uint32_t kNuMaxVertices = (1u << kNuDepth) * 2 * ((1u << kNuDepth) + 1);
static_assert(kNuMaxVertices == 40);

void VkKsquad::check_nonuniform_limits() const {
  const VkPhysicalDeviceLimits& limits = device_.limits();
  if (limits.maxGeometryOutputVertices < kNuMaxVertices ||
      limits.maxGeometryTotalOutputComponents < kNuMaxVertices * 7)
    throw vulkan::MissingFeature(
        fmt::format("vk-mode=nonuniform needs {} geometry output vertices of 7 components "
                    "(ksquad_nonuniform.geom)",
                    kNuMaxVertices));
}

std::vector<KsdieRecord> VkKsquad::ksdice() const {
  if (!settings_.is(Mapping::nonuniform) || patch_count_ == 0) return {};
  std::vector<int> records(patch_count_ * vk_ksquad::ksdie_slots(settings_.max_level) *
                           kNuKsdieInts);
  ksdice_.read(records.data(), records.size() * sizeof(int));
  return vk_ksquad::nonuniform_records(tables_, read_levels(), records, settings_.max_level);
}

// The geometry stage's emitted vertices; its counters go into the record's details (the runner
// reads device() after read_back()).
EvalResult VkKsquad::read_back_nonuniform() {
  const KsquadStatistics st = statistics();
  record_eq3_details(st);
  record_.details["nu_ksdice"] = std::to_string(st.ksdice);
  record_.details["nu_subdivided_linear"] = std::to_string(st.subdivided_linear);
  record_.details["nu_subdivided_boundary"] = std::to_string(st.subdivided_boundary);
  record_.details["nu_culled_frustum"] = std::to_string(st.culled_frustum);
  record_.details["nu_culled_back"] = std::to_string(st.culled_back);
  record_.details["nu_triangles"] = std::to_string(st.triangles);
  record_.details["nu_capped_edges"] = std::to_string(st.capped_edges);
  std::vector<float> slots(patch_count_ * vk_ksquad::ksdie_slots(settings_.max_level) * kNuLattice *
                           kNuLattice * kNuVertexFloats);
  positions_.read(slots.data(), slots.size() * sizeof(float));
  return vk_ksquad::nonuniform_result(tables_, slots, request_.normals, settings_.max_level,
                                      surface_count_);
}

}  // namespace nurbs::vk_ksquad
