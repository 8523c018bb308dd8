#include "strategies/glsl_deboor/span_runs.h"

#include "reference/nurbs_math.h"

namespace nurbs::glsl_deboor {

std::vector<SpanRun> bin_into_spans(const std::vector<double>& parameters, int degree, int count,
                                    const std::vector<double>& knots) {
  const std::vector<float> rounded(knots.begin(), knots.end());
  std::vector<SpanRun> runs;
  for (std::size_t a = 0; a < parameters.size(); ++a) {
    const int span = find_span(degree, count, rounded.data(), static_cast<float>(parameters[a]));
    if (!runs.empty() && runs.back().span == span)
      ++runs.back().count;
    else
      runs.push_back({span, static_cast<int>(a), 1});
  }
  return runs;
}

}  // namespace nurbs::glsl_deboor
