// Deterministic random knot vectors and surfaces for the reference tests. Every generated surface
// satisfies the rules of docs/design.md §Data model (the tests assert that with validate_surface),
// so a failure is about evaluation, never about a malformed input.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "reference/surface.h"

namespace nurbs::test {

using Rng = std::mt19937_64;

inline int uniform_int(Rng& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}
inline double uniform_real(Rng& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

enum class Ends { clamped, unclamped, mixed };

// count + degree + 1 knots: runs of equal values, the end runs of multiplicity <= degree+1
// (exactly degree+1 when clamped), interior runs <= degree (at most `max_interior` when given),
// and a non-empty domain [knots[degree], knots[count]]. Breakpoints are `scale * k` for integers
// k (step 1..4 between breakpoints), so scale = 1/8 gives small dyadic knots.
inline std::vector<double> random_knots(Rng& rng, int degree, int count, Ends ends,
                                        double scale = 0.125, int max_interior = 0) {
  const int total = count + degree + 1;
  const int interior_limit = max_interior > 0 ? std::min(max_interior, degree) : degree;
  for (;;) {
    bool clamp_start = ends == Ends::clamped, clamp_end = ends == Ends::clamped;
    if (ends == Ends::mixed) {
      clamp_start = uniform_int(rng, 0, 1) == 1;
      clamp_end = uniform_int(rng, 0, 1) == 1;
    }
    const int first = clamp_start ? degree + 1 : uniform_int(rng, 1, degree);
    const int last = clamp_end ? degree + 1 : uniform_int(rng, 1, degree);
    if (first + last > total) continue;
    std::vector<int> runs{first};
    int remaining = total - first - last;
    while (remaining > 0) {
      // Favour simple knots, but exercise full multiplicity often enough.
      int m = uniform_int(rng, 0, 3) == 0 ? uniform_int(rng, 1, interior_limit) : 1;
      m = std::min(m, remaining);
      runs.push_back(m);
      remaining -= m;
    }
    runs.push_back(last);
    std::vector<double> knots;
    long k = uniform_int(rng, -4, 4);
    for (int m : runs) {
      for (int r = 0; r < m; ++r) knots.push_back(scale * static_cast<double>(k));
      k += uniform_int(rng, 1, 4);
    }
    if (knots[degree] < knots[count]) return knots;
  }
}

// A surface whose data are small dyadic rationals: points k/64 in [-8, 8], weights k/8 in
// [1/4, 4] (all 1 when `rational` is false). Every double converts to a rational exactly, and
// small ones keep exact arithmetic fast.
inline Surface random_surface(Rng& rng, int degree_u, int degree_v, int count_u, int count_v,
                              Ends ends, bool rational, int max_interior = 0) {
  Surface s;
  s.name = "random";
  s.degree_u = degree_u;
  s.degree_v = degree_v;
  s.count_u = count_u;
  s.count_v = count_v;
  s.knots_u = random_knots(rng, degree_u, count_u, ends, 0.125, max_interior);
  s.knots_v = random_knots(rng, degree_v, count_v, ends, 0.125, max_interior);
  const std::size_t n = static_cast<std::size_t>(count_u) * count_v;
  for (std::size_t k = 0; k < n; ++k) {
    s.points.push_back({uniform_int(rng, -512, 512) / 64.0, uniform_int(rng, -512, 512) / 64.0,
                        uniform_int(rng, -512, 512) / 64.0});
    s.weights.push_back(rational ? uniform_int(rng, 2, 32) / 8.0 : 1.0);
  }
  return s;
}

// Parameters worth testing in [knots[degree], knots[count]]: both ends, every distinct knot in
// the domain, and `random_count` uniformly random doubles.
inline std::vector<double> test_parameters(Rng& rng, const std::vector<double>& knots, int degree,
                                           int count, int random_count) {
  const double lo = knots[degree], hi = knots[count];
  std::vector<double> t{lo, hi};
  for (int k = degree + 1; k < count; ++k)
    if (knots[k] > lo && knots[k] < hi && knots[k] != t.back()) t.push_back(knots[k]);
  for (int r = 0; r < random_count; ++r) t.push_back(uniform_real(rng, lo, hi));
  return t;
}

}  // namespace nurbs::test
