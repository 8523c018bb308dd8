// 002 §3.3.2 on the host: the evaluation parameters of one direction binned into the non-empty
// knot spans they fall in (A2.1 FindSpan), with parameters and knots rounded to float as the
// shader sees them: a span two knots of a real model round into (linkrods.step: 1.8e-8 apart near
// 3.6) would make de Boor divide 0 by 0; the search never returns one. Each run becomes one quad
// drawn with its span index and knots as uniforms, so the device never searches.
#pragma once

#include <vector>

namespace nurbs::glsl_deboor {

struct SpanRun {
  int span = 0;   // knots[span] <= parameter < knots[span + 1] (end parameter: last span)
  int first = 0;  // first sample index of the run
  int count = 0;  // consecutive samples in that span
};

// Consecutive samples with the same span form one run; sorted parameters (grid, span grid) give
// one run per non-empty span that holds samples.
std::vector<SpanRun> bin_into_spans(const std::vector<double>& parameters, int degree, int count,
                                    const std::vector<double>& knots);

}  // namespace nurbs::glsl_deboor
