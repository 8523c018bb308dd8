#include "reference/sampling.h"

#include <fmt/format.h>

#include <stdexcept>

#include "reference/tspline.h"
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

namespace {

std::size_t nonempty_spans(const std::vector<double>& knots, int degree, int count) {
  std::size_t spans = 0;
  for (int s = degree; s < count; ++s) spans += knots[s] < knots[s + 1] ? 1 : 0;
  return spans;
}

// A T-spline's "spans" are the cells between its knot lines (every local knot inside the domain):
// on each, every blending function is one polynomial, as on a NURBS span.
std::vector<double> tspline_breaks_u(const TSplineSurface& t) {
  return tspline_cell_breaks(t.knots_u, t.u_min, t.u_max);
}
std::vector<double> tspline_breaks_v(const TSplineSurface& t) {
  return tspline_cell_breaks(t.knots_v, t.v_min, t.v_max);
}

// The breaks as a clamped knot vector of degree 0 (count = cells), so span_grid_parameters serves
// both kinds.
std::vector<double> span_grid_of_breaks(const std::vector<double>& breaks, int steps) {
  return span_grid_parameters(breaks, 0, static_cast<int>(breaks.size()) - 1, steps);
}

// The samples a request asks for, from the sizes alone: checked before any parameter list is
// allocated (many-4096 at 65536x65536 would otherwise build 4 GiB of lists only to refuse them).
// In double: a span grid's count can pass 2^64 (2^20 spans x 4097 steps, squared), and the limit
// is far inside double's exact integers.
double requested_samples(const Scene& scene, const Sampling& sampling) {
  double total = 0;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    switch (sampling.mode) {
      case SamplingMode::grid:
        total += static_cast<double>(sampling.grid_u) * sampling.grid_v;
        break;
      case SamplingMode::span_grid:
        if (s.is_tspline()) {
          total += static_cast<double>((tspline_breaks_u(*s.tspline).size() - 1) *
                                       (sampling.span_steps + 1)) *
                   static_cast<double>((tspline_breaks_v(*s.tspline).size() - 1) *
                                       (sampling.span_steps + 1));
          break;
        }
        total += static_cast<double>(nonempty_spans(s.knots_u, s.degree_u, s.count_u) *
                                     (sampling.span_steps + 1)) *
                 static_cast<double>(nonempty_spans(s.knots_v, s.degree_v, s.count_v) *
                                     (sampling.span_steps + 1));
        break;
      case SamplingMode::explicit_list:
        if (i < sampling.explicit_uv.size())
          total += static_cast<double>(sampling.explicit_uv[i].size());
        break;
    }
  }
  return total;
}

}  // namespace

std::vector<SurfaceSamples> sample_parameters(const Scene& scene, const Sampling& sampling) {
  switch (sampling.mode) {
    case SamplingMode::grid:
      if (sampling.grid_u < 2 || sampling.grid_v < 2 || sampling.grid_u > kMaxGridPerDirection ||
          sampling.grid_v > kMaxGridPerDirection)
        throw InputError(fmt::format("grid {}x{}: each side must be in 2..{}", sampling.grid_u,
                                     sampling.grid_v, kMaxGridPerDirection));
      break;
    case SamplingMode::span_grid:
      if (sampling.span_steps < 1 || sampling.span_steps > kMaxSpanSteps)
        throw InputError(
            fmt::format("span samples {}: must be in 1..{}", sampling.span_steps, kMaxSpanSteps));
      break;
    case SamplingMode::explicit_list:
      if (sampling.explicit_uv.size() != scene.surfaces.size())
        throw InputError(fmt::format("explicit samples given for {} surfaces, scene has {}",
                                     sampling.explicit_uv.size(), scene.surfaces.size()));
      break;
  }
  if (const double total = requested_samples(scene, sampling);
      total > static_cast<double>(kMaxSamplesPerRequest))
    throw InputError(
        fmt::format("{:.0f} samples over {} surfaces: more than the limit of {} per "
                    "request",
                    total, scene.surfaces.size(), kMaxSamplesPerRequest));

  std::vector<SurfaceSamples> out(scene.surfaces.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    switch (sampling.mode) {
      case SamplingMode::grid:
        out[i].u = grid_parameters(s.u_min(), s.u_max(), sampling.grid_u);
        out[i].v = grid_parameters(s.v_min(), s.v_max(), sampling.grid_v);
        break;
      case SamplingMode::span_grid:
        if (s.is_tspline()) {
          out[i].u = span_grid_of_breaks(tspline_breaks_u(*s.tspline), sampling.span_steps);
          out[i].v = span_grid_of_breaks(tspline_breaks_v(*s.tspline), sampling.span_steps);
          break;
        }
        out[i].u = span_grid_parameters(s.knots_u, s.degree_u, s.count_u, sampling.span_steps);
        out[i].v = span_grid_parameters(s.knots_v, s.degree_v, s.count_v, sampling.span_steps);
        break;
      case SamplingMode::explicit_list:
        out[i].tensor = false;
        for (const auto& uv : sampling.explicit_uv[i]) {
          out[i].u.push_back(uv[0]);
          out[i].v.push_back(uv[1]);
        }
        break;
    }
  }
  return out;
}

std::size_t total_samples(const std::vector<SurfaceSamples>& samples) {
  std::size_t n = 0;
  for (const SurfaceSamples& s : samples) n += s.count();
  return n;
}

}  // namespace nurbs
