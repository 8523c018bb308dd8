#include <fmt/format.h>

#include <algorithm>

#include "strategies/strategy.h"

namespace nurbs {

std::string sampling_mode_name(SamplingMode mode) {
  switch (mode) {
    case SamplingMode::grid:
      return "grid";
    case SamplingMode::span_grid:
      return "span_grid";
    case SamplingMode::explicit_list:
      break;
  }
  return "explicit";
}

std::optional<std::string> refusal_reason(const Capabilities& caps, const Scene& scene,
                                          const EvalRequest& request) {
  if (!caps.supports(request.precision))
    return fmt::format("precision {} not supported", to_string(request.precision));
  if (!caps.sampling.supports(request.sampling.mode))
    return fmt::format("sampling mode {} not supported", sampling_mode_name(request.sampling.mode));
  if (request.normals && !caps.normals) return std::string("normals not supported");
  for (const Surface& s : scene.surfaces) {
    if (std::max(s.degree_u, s.degree_v) > caps.max_degree)
      return fmt::format("surface '{}' has degree {}x{}, the strategy supports at most {}", s.name,
                         s.degree_u, s.degree_v, caps.max_degree);
    if (!caps.rational && s.is_rational())
      return fmt::format("surface '{}' is rational, the strategy is polynomial only", s.name);
  }
  return std::nullopt;
}

void refuse_unsupported(std::string_view strategy, const Capabilities& caps, const Scene& scene,
                        const EvalRequest& request) {
  if (auto reason = refusal_reason(caps, scene, request))
    throw RefusedError(fmt::format("{}: {}", strategy, *reason));
}

}  // namespace nurbs
