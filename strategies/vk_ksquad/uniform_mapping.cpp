#include "strategies/vk_ksquad/uniform_mapping.h"

#include <bit>

#include "strategies/vk_ksquad/ksquad_layout.h"
#include "strategies/vk_ksquad/patches.h"

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
                                   0,
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

}  // namespace nurbs::vk_ksquad
