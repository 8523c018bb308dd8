// The KSQuads of a scene (003 §2): one per pair of non-empty knot spans (u span, v span) of a
// surface that holds samples -- at most (r - 2p)(s - 2q) per surface -- with the runs of the
// request's u- and v-parameters that fall in them. Shared by every KSQuad strategy (cl-stair,
// vk-ksquad): the host bins the parameters once, so no device ever searches a span.
#pragma once

#include <vector>

#include "reference/nurbs_math.h"
#include "reference/sampling.h"

namespace nurbs::ksquad {

// `count` consecutive parameters from index `begin` lie in knot span `span`.
struct SpanRun {
  int span = 0, begin = 0, count = 0;
};

// Runs of equal span over a non-decreasing parameter list, the span found (A2.1) with the
// parameter and knots rounded to T, as the device sees them.
template <typename T>
std::vector<SpanRun> runs_of_grid(const std::vector<double>& params, int degree, int count,
                                  const std::vector<T>& knots) {
  std::vector<SpanRun> runs;
  for (std::size_t a = 0; a < params.size(); ++a) {
    const int s = find_span(degree, count, knots.data(), T(params[a]));
    if (runs.empty() || runs.back().span != s)
      runs.push_back({s, static_cast<int>(a), 1});
    else
      ++runs.back().count;
  }
  return runs;
}

// Span grid natively: the k-th run of steps + 1 parameters is the k-th non-empty span's (its end
// knot included, as sample_parameters lists it). A span non-empty in double but empty once its
// knots are rounded to T (real models: knots 1.8e-8 apart near 3.6) holds parameters that all
// round to its one knot value: they are evaluated in the span the rounded search gives there
// (the next non-empty one), whose constants are finite; the surface is continuous, so that is
// the same point.
template <typename T>
std::vector<SpanRun> runs_of_span_grid(const std::vector<double>& knots, int degree, int count,
                                       int steps) {
  const std::vector<T> rounded(knots.begin(), knots.end());
  std::vector<SpanRun> runs;
  for (int s = degree; s < count; ++s)
    if (knots[s] < knots[s + 1]) {
      const int span =
          rounded[s] < rounded[s + 1] ? s : find_span(degree, count, rounded.data(), rounded[s]);
      runs.push_back({span, static_cast<int>(runs.size()) * (steps + 1), steps + 1});
    }
  return runs;
}

struct KSQuad {
  int surface = 0;
  SpanRun u, v;
};

// Every KSQuad of the scene for a grid or span-grid request, surface by surface, u-run major.
template <typename T>
std::vector<KSQuad> build_ksquads(const Scene& scene, const std::vector<SurfaceSamples>& samples,
                                  const Sampling& sampling) {
  std::vector<KSQuad> quads;
  const bool span_grid = sampling.mode == SamplingMode::span_grid;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    const std::vector<T> ku(s.knots_u.begin(), s.knots_u.end());
    const std::vector<T> kv(s.knots_v.begin(), s.knots_v.end());
    const auto ru =
        span_grid ? runs_of_span_grid<T>(s.knots_u, s.degree_u, s.count_u, sampling.span_steps)
                  : runs_of_grid(samples[i].u, s.degree_u, s.count_u, ku);
    const auto rv =
        span_grid ? runs_of_span_grid<T>(s.knots_v, s.degree_v, s.count_v, sampling.span_steps)
                  : runs_of_grid(samples[i].v, s.degree_v, s.count_v, kv);
    for (const SpanRun& a : ru)
      for (const SpanRun& b : rv) quads.push_back({static_cast<int>(i), a, b});
  }
  return quads;
}

}  // namespace nurbs::ksquad
