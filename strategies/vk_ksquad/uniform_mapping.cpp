#include "strategies/vk_ksquad/uniform_mapping.h"

#include <bit>
#include <cstdint>
#include <utility>

#include "strategies/vk_ksquad/ksquad_layout.h"
#include "strategies/vk_ksquad/patches.h"
#include "strategies/vk_ksquad/vk_ksquad_class.h"

namespace nurbs::vk_ksquad {

SurfaceTable surface_table(const Scene& scene, const std::vector<SurfaceSamples>& samples) {
  SurfaceTable out;
  std::size_t point_base = 0;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    const SurfaceSamples& sm = samples[i];
    const int param_u = static_cast<int>(out.params.size());
    for (double u : sm.u) out.params.push_back(static_cast<float>(u));
    const int param_v = static_cast<int>(out.params.size());
    for (double v : sm.v) out.params.push_back(static_cast<float>(v));
    const int rec[kSurfaceInts] = {s.degree_u,
                                   s.degree_v,
                                   s.count_u,
                                   s.count_v,
                                   static_cast<int>(point_base),
                                   param_u,
                                   param_v,
                                   static_cast<int>(sm.v.size()),
                                   static_cast<int>(out.total),
                                   0,
                                   std::bit_cast<int>(1.0f),  // threshold scale
                                   0,
                                   std::bit_cast<int>(static_cast<float>(s.u_min())),
                                   std::bit_cast<int>(static_cast<float>(s.u_max())),
                                   std::bit_cast<int>(static_cast<float>(s.v_min())),
                                   std::bit_cast<int>(static_cast<float>(s.v_max()))};
    out.surfaces.insert(out.surfaces.end(), rec, rec + kSurfaceInts);
    point_base += s.points.size();
    out.total += sm.count();
  }
  return out;
}

std::vector<ksquad::KSQuad> grid_ksquads(const Scene& scene,
                                         const std::vector<SurfaceSamples>& samples) {
  std::vector<ksquad::KSQuad> quads;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    const std::vector<float> ku(s.knots_u.begin(), s.knots_u.end());
    const std::vector<float> kv(s.knots_v.begin(), s.knots_v.end());
    const auto ru =
        vk_ksquad::with_empty_spans(ksquad::runs_of_grid(samples[i].u, s.degree_u, s.count_u, ku),
                                    s.knots_u, s.degree_u, s.count_u);
    const auto rv =
        vk_ksquad::with_empty_spans(ksquad::runs_of_grid(samples[i].v, s.degree_v, s.count_v, kv),
                                    s.knots_v, s.degree_v, s.count_v);
    for (const ksquad::SpanRun& a : ru)
      for (const ksquad::SpanRun& b : rv) quads.push_back({static_cast<int>(i), a, b});
  }
  return quads;
}

// The span grid's samples as the device evaluated them: a tensor when every lattice column
// (row) got the same u (v) -- the tessellator's coordinates k / level are the same on every
// edge of a patch and both sides of a knot line blend to the knot exactly -- else the
// explicit list of the (u, v) pairs.
SurfaceSamples chosen_samples(const SurfaceSamples& requested, const float* uv) {
  const std::size_t nu = requested.u.size(), nv = requested.v.size();
  SurfaceSamples out;
  for (std::size_t a = 0; a < nu; ++a) out.u.push_back(uv[2 * a * nv]);
  for (std::size_t b = 0; b < nv; ++b) out.v.push_back(uv[2 * b + 1]);
  for (std::size_t k = 0; k < nu * nv; ++k)
    if (uv[2 * k] != out.u[k / nv] || uv[2 * k + 1] != out.v[k % nv]) {
      out = {};
      out.tensor = false;
      for (std::size_t j = 0; j < nu * nv; ++j) {
        out.u.push_back(uv[2 * j]);
        out.v.push_back(uv[2 * j + 1]);
      }
      break;
    }
  return out;
}

// ksquad.frag's per-surface trim row (VkKsquad::trim_surface_rows)
constexpr int kTrimSurfaceInts = 5;

// VkKsquad's uniform mapping (the requested lattice -- not 003 §4's "uniform" mapping, which is
// the adaptive one: levels from the runs; direct trimming).

// Direct trimming (uniform mode): one compute dispatch per trimmed surface; the masks stay on
// the device until read_back(). On a span grid the samples are the tessellator's (16.16 fixed
// point: up to ~T/2 * 2^-17 of a span off the requested lattice), and those are what the
// positions and the scoring use, so they are what is classified: read once after the first
// evaluate() of a prepare (the tessellator is deterministic), sample by sample where they are
// no longer a tensor grid.
bool VkKsquad::classify() {
  if (classifier_.trims() && span_grid_samples() && !classifying_chosen_samples_) {
    std::vector<float> uv(total_ * 2);
    sample_params_.read(uv.data(), uv.size() * sizeof(float));
    std::vector<SurfaceSamples> chosen;
    std::size_t base = 0;
    for (const SurfaceSamples& s : samples_) {
      chosen.push_back(vk_ksquad::chosen_samples(s, uv.data() + 2 * base));
      base += s.count();
    }
    classifier_.set_samples(chosen);
    classifying_chosen_samples_ = true;
  }
  if (classifier_.trims())
    device_.submit_and_wait([&](VkCommandBuffer cb) { classifier_.record(cb); });
  classified_ = true;
  return true;
}

void VkKsquad::read_back_uniform(EvalResult& out) {
  vk_ksquad::read_uniform_capture(out, samples_, positions_,
                                  span_grid_samples() ? &sample_params_ : nullptr,
                                  request_.normals ? &normals_ : nullptr);
  if (classified_ && classifier_.trims()) {
    trim_direct::Cost cost;
    auto masks = classifier_.read_masks(cost);
    trim_direct::record_cost(cost, record_);
    for (std::size_t i = 0; i < out.surfaces.size(); ++i)
      out.surfaces[i].inside = std::move(masks[i]);
  }
}

// ksquad.frag's per-surface trim row: tables base (-1: untrimmed), the local frame's origin and
// ε as float bits, the iteration limit.
std::vector<std::int32_t> VkKsquad::trim_surface_rows() const {
  std::vector<std::int32_t> rows;
  for (const auto& st : classifier_.tables().surfaces)
    rows.insert(rows.end(), {st.base, std::bit_cast<std::int32_t>(static_cast<float>(st.origin_u)),
                             std::bit_cast<std::int32_t>(static_cast<float>(st.origin_v)),
                             std::bit_cast<std::int32_t>(st.epsilon), trim_settings_.iterations});
  static_assert(kTrimSurfaceInts == 5);
  return rows;
}

// Uniform span grid: the tessellator chooses the parameters (ksquad.tese span_parameter).
bool VkKsquad::span_grid_samples() const {
  return !settings_.camera_levels() && request_.sampling.mode == SamplingMode::span_grid;
}

}  // namespace nurbs::vk_ksquad
