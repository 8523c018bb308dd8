#include "strategies/vk_ksquad/adaptive_mapping.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "reference/nurbs_math.h"
#include "strategies/vk_ksquad/nonuniform_mapping.h"
#include "strategies/vk_ksquad/patches.h"
#include "strategies/vk_ksquad/vk_ksquad_class.h"

namespace nurbs::vk_ksquad {

// One corner per (distinct knot value in u, distinct knot value in v) of each surface's domain;
// Corners::index maps (surface, first knot index of the u value, first knot index of the v
// value) to its row. vk-corners=host: S(x_k, y_l) by the reference, rounded to float (003's
// "without any precomputation on the CPU" is the device path; this one measures the
// difference). device: zeros, filled by the corner pass; Corners::spans gets, per corner, the
// span pair A2.1 assigns its knots to and whether each knot is that span's end (the domain's
// end knot).
Corners corner_table(const Scene& scene, bool on_host) {
  Corners out;
  std::vector<float>& corners = out.rows;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    const SurfaceNet<double> net(s);
    const auto breaks = [](const std::vector<double>& k, int p, int n) {
      std::vector<int> at;  // first knot index of each distinct value in [k_p, k_n]
      for (int a = p; a <= n; ++a)
        if (a == p || k[a] > k[a - 1]) at.push_back(a);
      return at;
    };
    // A2.1: the span [k_j, k_j+1) holding k_a (non-empty), or the last one at the end
    const auto span_of = [](const std::vector<double>& k, int a, int n) {
      int j = a;
      while (j < n && k[j + 1] == k[a]) ++j;
      if (j < n) return std::make_pair(j, 0);
      while (!(k[j - 1] < k[j])) --j;
      return std::make_pair(j - 1, 1);
    };
    for (int a : breaks(s.knots_u, s.degree_u, s.count_u))
      for (int b : breaks(s.knots_v, s.degree_v, s.count_v)) {
        out.index[{static_cast<int>(i), a, b}] = static_cast<int>(corners.size() / 4);
        const auto [span_u, end_u] = span_of(s.knots_u, a, s.count_u);
        const auto [span_v, end_v] = span_of(s.knots_v, b, s.count_v);
        out.spans.push_back({static_cast<int>(i), span_u, span_v, end_u, end_v});
        if (!on_host) {
          corners.insert(corners.end(), {0.0f, 0.0f, 0.0f, 1.0f});
          continue;
        }
        const Vec3<double> p = surface_point(net, s.knots_u[a], s.knots_v[b]);
        corners.insert(corners.end(), {static_cast<float>(p[0]), static_cast<float>(p[1]),
                                       static_cast<float>(p[2]), 1.0f});
      }
  }
  return out;
}

int Corners::at(const Surface& s, int surface, int a, int b) const {
  while (a > s.degree_u && s.knots_u[a - 1] == s.knots_u[a]) --a;
  while (b > s.degree_v && s.knots_v[b - 1] == s.knots_v[b]) --b;
  return index.at({surface, a, b});
}

KsquadStatistics adaptive_statistics(KsquadStatistics st, const HostTables& tables,
                                     const std::vector<float>& levels, int most_level,
                                     bool nonuniform) {
  st.implied_vertices = 0;
  st.tessellated_triangles = 0;
  st.max_level = 0;
  const float most = static_cast<float>(most_level);
  // per KSQuad (surface, span_u, span_v): the segments of its four outer edges
  std::map<std::array<int, 3>, std::array<float, 4>> edge_segments;
  for (std::size_t k = 0; k < tables.patch_count(); ++k) {
    const float* o = &levels[8 * k];
    const int* row = &tables.patches[kPatchInts * k];
    if (row[kPatchPiece] == 0) {  // once per KSQuad
      std::array<float, 4> segments{};
      for (int e = 0; e < 4; ++e) {
        st.capped_edges += o[4 + e] > most;
        // adaptive: the KSQuad edge's level (its pieces share it out); nonuniform: one piece,
        // whose outer levels are its lattice's
        segments[e] = nonuniform ? o[e] : std::min(o[4 + e], most);
      }
      edge_segments[{row[0], row[1], row[2]}] = segments;
    }
    if (o[0] <= 0) continue;  // a piece the KSQuad did not need: discarded
    const int i0 = static_cast<int>(std::max({o[1], o[3], 2.0f}));
    const int i1 = static_cast<int>(std::max({o[0], o[2], 2.0f}));
    st.implied_vertices += static_cast<std::uint64_t>(o[0] + o[1] + o[2] + o[3]) +
                           static_cast<std::uint64_t>(i0 - 1) * (i1 - 1);
    // the inner levels as the control stage set them (ksquad.tesc)
    st.tessellated_triangles += quad_domain_triangles(o, i0, i1);
    for (int e = 0; e < 4; ++e) st.max_level = std::max(st.max_level, static_cast<int>(o[e]));
  }
  // A KSQuad's edge u = x_i+1 (2) is the next KSQuad's in u edge u = x_i (0) -- every non-empty
  // span pair is a KSQuad here, so the next u span is the first key past (surface, span_u, max) --
  // and v likewise (3 against 1).
  st.shared_edges = st.cracked_edges = 0;
  for (auto it = edge_segments.begin(); it != edge_segments.end(); ++it) {
    const auto& [key, segments] = *it;
    const auto after = edge_segments.upper_bound({key[0], key[1], std::numeric_limits<int>::max()});
    if (after != edge_segments.end() && after->first[0] == key[0])
      if (const auto next_u = edge_segments.find({key[0], after->first[1], key[2]});
          next_u != edge_segments.end()) {
        ++st.shared_edges;
        st.cracked_edges += next_u->second[0] != segments[2];
      }
    const auto next_v = std::next(it);  // same surface and u span: the next v span
    if (next_v != edge_segments.end() && next_v->first[0] == key[0] && next_v->first[1] == key[1]) {
      ++st.shared_edges;
      st.cracked_edges += next_v->second[1] != segments[3];
    }
  }
  return st;
}

std::vector<PatchLevels> adaptive_patch_levels(const HostTables& tables,
                                               const std::vector<float>& levels) {
  std::vector<PatchLevels> out;
  for (std::size_t k = 0; k < tables.patch_count(); ++k) {
    PatchLevels p;
    const int* row = &tables.patches[kPatchInts * k];
    p.surface = row[0];
    p.span_u = row[1];
    p.span_v = row[2];
    std::copy_n(&levels[8 * k], 4, p.set.begin());
    std::copy_n(&levels[8 * k + 4], 4, p.wanted.begin());
    out.push_back(p);
  }
  return out;
}

// Adaptive mode: every captured vertex on each KSQuad's four edges, keyed by the edge; a
// KSQuad cut into pieces contributes the vertices of all its pieces, each (u, v) once.
std::vector<CapturedEdge> adaptive_edges(const HostTables& tables, const std::vector<float>& slots,
                                         std::size_t region, int max_level) {
  std::vector<CapturedEdge> edges;
  const int per_edge = max_level + 1;
  std::map<std::array<int, 3>, std::size_t> first_edge;  // KSQuad -> its edges in `edges`
  for (std::size_t k = 0; k < tables.patch_count(); ++k) {
    const int* row = &tables.patches[kPatchInts * k];
    auto [it, added] = first_edge.try_emplace({row[0], row[1], row[2]}, edges.size());
    if (added) {
      const float* c_u = &tables.constants[row[3]];
      const float* c_v = &tables.constants[row[4]];
      const int pu = tables.surfaces[kSurfaceInts * row[0]];
      const int pv = tables.surfaces[kSurfaceInts * row[0] + 1];
      const float u0 = c_u[pu - 1], u1 = c_u[pu], v0 = c_v[pv - 1], v1 = c_v[pv];
      // outer edge e: u = u0 (0), v = v0 (1), u = u1 (2), v = v1 (3)
      edges.push_back({row[0], 0, u0, v0, v1, {}});
      edges.push_back({row[0], 1, v0, u0, u1, {}});
      edges.push_back({row[0], 0, u1, v0, v1, {}});
      edges.push_back({row[0], 1, v1, u0, u1, {}});
    }
    // A corner's slot is on one edge only (ksquad.tese: adaptive_slot); an edge holds every
    // edge-slot vertex whose (u, v) lies on it (t = 0 and 1 give the knots exactly).
    for (int j = 0; j < 4 * per_edge; ++j) {
      const float* slot = &slots[kSlotFloats * (k * region + j)];
      if (std::isnan(slot[0])) continue;
      for (int e = 0; e < 4; ++e) {
        CapturedEdge& edge = edges[it->second + e];
        if (slot[edge.direction] != edge.fixed) continue;
        const bool known =
            std::any_of(edge.vertices.begin(), edge.vertices.end(),
                        [&](const auto& v) { return v[0] == slot[0] && v[1] == slot[1]; });
        if (!known) edge.vertices.push_back({slot[0], slot[1], slot[2], slot[3], slot[4]});
      }
    }
  }
  return edges;
}

CapturedSamples::CapturedSamples(std::size_t surface_count, bool normals)
    : normals_(normals), xyz_(surface_count), normal_(surface_count) {
  out_.surfaces.resize(surface_count);
  for (SurfaceResult& r : out_.surfaces) r.samples.tensor = false;
}

void CapturedSamples::add(int surface, const float* uvxyz, const float* normal) {
  out_.surfaces[surface].samples.u.push_back(uvxyz[0]);
  out_.surfaces[surface].samples.v.push_back(uvxyz[1]);
  xyz_[surface].insert(xyz_[surface].end(), uvxyz + 2, uvxyz + 5);
  if (normals_) normal_[surface].insert(normal_[surface].end(), normal, normal + 3);
}

EvalResult CapturedSamples::result() {
  for (std::size_t i = 0; i < out_.surfaces.size(); ++i) {
    SurfaceResult& r = out_.surfaces[i];
    r.positions = PointArray(Precision::f32, r.samples.count());
    std::memcpy(r.positions.f32(), xyz_[i].data(), xyz_[i].size() * sizeof(float));
    if (normals_) {
      r.normals = PointArray(Precision::f32, r.samples.count());
      std::memcpy(r.normals.f32(), normal_[i].data(), normal_[i].size() * sizeof(float));
    }
  }
  return std::move(out_);
}

EvalResult adaptive_result(const HostTables& tables, const std::vector<float>& slots,
                           const std::vector<float>& slot_normals, std::size_t region,
                           std::size_t surface_count) {
  CapturedSamples out(surface_count, !slot_normals.empty());
  for (std::size_t k = 0; k < tables.patch_count(); ++k) {
    const int surface = tables.patches[kPatchInts * k];
    for (std::size_t j = 0; j < region; ++j) {
      const float* slot = &slots[kSlotFloats * (k * region + j)];
      if (std::isnan(slot[0])) continue;
      out.add(surface, slot, slot_normals.empty() ? nullptr : &slot_normals[3 * (k * region + j)]);
    }
  }
  return out.result();
}

constexpr std::uint32_t kCornerGroup = 64;  // ksquad_corners.comp: local_size_x

// VkKsquad's adaptive mapping (003 §3.1 eq. 3 in the control stage), also the first half of the
// nonuniform one: the corner pass and what the control stage chose.

// Adaptive mode: the levels the control stage chose, read back from its storage buffer.
KsquadStatistics VkKsquad::statistics() const {
  if (!settings_.camera_levels() || patch_count_ == 0) return stats_;
  const KsquadStatistics st = vk_ksquad::adaptive_statistics(stats_, tables_, read_levels(),
                                                             settings_.max_level * settings_.pieces,
                                                             settings_.is(Mapping::nonuniform));
  return settings_.is(Mapping::nonuniform) ? vk_ksquad::nonuniform_statistics(st, ksdice()) : st;
}

std::vector<float> VkKsquad::read_levels() const {
  std::vector<float> levels(8 * patch_count_);
  levels_.read(levels.data(), levels.size() * sizeof(float));
  return levels;
}

std::vector<PatchLevels> VkKsquad::patch_levels() const {
  if (!settings_.camera_levels() || patch_count_ == 0) return {};
  return vk_ksquad::adaptive_patch_levels(tables_, read_levels());
}

std::vector<CapturedEdge> VkKsquad::captured_edges() const {
  if (!settings_.camera_levels() || settings_.is(Mapping::nonuniform)) return {};
  return vk_ksquad::adaptive_edges(tables_, read_slots(), region_, settings_.max_level);
}

std::vector<float> VkKsquad::read_slots() const {
  std::vector<float> slots(patch_count_ * region_ * kSlotFloats);
  positions_.read(slots.data(), slots.size() * sizeof(float));
  return slots;
}

EvalResult VkKsquad::read_back_adaptive() {
  record_eq3_details(statistics());
  std::vector<float> slot_normals(request_.normals ? patch_count_ * region_ * 3 : 0);
  if (!slot_normals.empty())
    normals_.read(slot_normals.data(), slot_normals.size() * sizeof(float));
  return vk_ksquad::adaptive_result(tables_, read_slots(), slot_normals, region_, surface_count_);
}

// What eq. 3's reading (vk-eq3) and thresholds gave, for the record (the runner reads device()
// after read_back()).
void VkKsquad::record_eq3_details(const KsquadStatistics& st) {
  record_.details["eq3_shared_edges"] = std::to_string(st.shared_edges);
  record_.details["eq3_cracked_edges"] = std::to_string(st.cracked_edges);
  record_.details["eq3_max_level"] = std::to_string(st.max_level);
  if (!settings_.is(Mapping::nonuniform))
    record_.details["tessellated_triangles"] = std::to_string(st.tessellated_triangles);
}

// vk-corners=device: the corner pass, then a barrier so the control stage reads its corners.
void VkKsquad::record_corners(VkCommandBuffer cb) const {
  if (!settings_.camera_levels() || !settings_.device_corners || corner_jobs_.empty()) return;
  const auto count = static_cast<std::uint32_t>(corner_jobs_.size() / kCornerInts);
  corner_pass_->bind(cb, *set_);
  ModeConstants mode = mode_;
  mode.patch_base = static_cast<std::int32_t>(count);
  vkCmdPushConstants(cb, corner_pass_->layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof mode,
                     &mode);
  vkCmdDispatch(cb, (count + kCornerGroup - 1) / kCornerGroup, 1, 1);
  vulkan::memory_barrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                         VK_PIPELINE_STAGE_TESSELLATION_CONTROL_SHADER_BIT,
                         VK_ACCESS_SHADER_READ_BIT);
}

}  // namespace nurbs::vk_ksquad
