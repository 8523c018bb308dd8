#include "reference/sampling.h"

#include <fmt/format.h>

#include <stdexcept>

#include "reference/validation.h"

namespace nurbs {

std::string Sampling::label() const {
  switch (mode) {
    case SamplingMode::grid:
      return fmt::format("{}x{}", grid_u, grid_v);
    case SamplingMode::span_grid:
      return fmt::format("span{}", span_steps);
    case SamplingMode::explicit_list:
      break;
  }
  return "explicit";
}

std::vector<double> grid_parameters(double lo, double hi, int n) {
  std::vector<double> t(static_cast<std::size_t>(n));
  for (int a = 0; a < n; ++a) t[a] = lo + (hi - lo) * (static_cast<double>(a) / (n - 1));
  t.back() = hi;
  return t;
}

std::vector<double> span_grid_parameters(const std::vector<double>& knots, int degree, int count,
                                         int steps) {
  std::vector<double> t;
  for (int s = degree; s < count; ++s) {
    if (!(knots[s] < knots[s + 1])) continue;
    for (int k = 0; k <= steps; ++k)
      t.push_back(k == steps
                      ? knots[s + 1]
                      : knots[s] + (knots[s + 1] - knots[s]) * (static_cast<double>(k) / steps));
  }
  return t;
}

std::vector<SurfaceSamples> sample_parameters(const Scene& scene, const Sampling& sampling) {
  std::vector<SurfaceSamples> out(scene.surfaces.size());
  switch (sampling.mode) {
    case SamplingMode::grid:
      if (sampling.grid_u < 2 || sampling.grid_v < 2 || sampling.grid_u > kMaxGridPerDirection ||
          sampling.grid_v > kMaxGridPerDirection)
        throw InputError(fmt::format("grid {}x{}: each side must be in 2..{}", sampling.grid_u,
                                     sampling.grid_v, kMaxGridPerDirection));
      for (std::size_t i = 0; i < out.size(); ++i) {
        const Surface& s = scene.surfaces[i];
        out[i].u = grid_parameters(s.u_min(), s.u_max(), sampling.grid_u);
        out[i].v = grid_parameters(s.v_min(), s.v_max(), sampling.grid_v);
      }
      break;
    case SamplingMode::span_grid:
      if (sampling.span_steps < 1 || sampling.span_steps > kMaxSpanSteps)
        throw InputError(
            fmt::format("span samples {}: must be in 1..{}", sampling.span_steps, kMaxSpanSteps));
      for (std::size_t i = 0; i < out.size(); ++i) {
        const Surface& s = scene.surfaces[i];
        out[i].u = span_grid_parameters(s.knots_u, s.degree_u, s.count_u, sampling.span_steps);
        out[i].v = span_grid_parameters(s.knots_v, s.degree_v, s.count_v, sampling.span_steps);
      }
      break;
    case SamplingMode::explicit_list:
      if (sampling.explicit_uv.size() != out.size())
        throw InputError(fmt::format("explicit samples given for {} surfaces, scene has {}",
                                     sampling.explicit_uv.size(), out.size()));
      for (std::size_t i = 0; i < out.size(); ++i) {
        out[i].tensor = false;
        for (const auto& uv : sampling.explicit_uv[i]) {
          out[i].u.push_back(uv[0]);
          out[i].v.push_back(uv[1]);
        }
      }
      break;
  }
  // Checked on the parameter lists, before any per-sample memory is allocated anywhere.
  std::size_t total = 0;
  for (const SurfaceSamples& s : out) total += s.count();
  if (total > kMaxSamplesPerRequest)
    throw InputError(
        fmt::format("{} samples over {} surfaces: more than the limit of {} per request", total,
                    out.size(), kMaxSamplesPerRequest));
  return out;
}

std::size_t total_samples(const std::vector<SurfaceSamples>& samples) {
  std::size_t n = 0;
  for (const SurfaceSamples& s : samples) n += s.count();
  return n;
}

}  // namespace nurbs
