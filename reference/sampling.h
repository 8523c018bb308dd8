// Where a request evaluates each surface (docs/design.md §Sampling). Grid and span grid are tensor
// products of a u-list and a v-list, so separable evaluators serve both through one code path;
// the explicit list is not separable.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "reference/surface.h"

namespace nurbs {

enum class SamplingMode { grid, span_grid, explicit_list };

struct Sampling {
  SamplingMode mode = SamplingMode::grid;
  int grid_u = 64, grid_v = 64;  // grid: NU x NV samples over the domain, ends included
  int span_steps = 4;            // span grid: every non-empty span split into T steps
  // explicit list: the (u, v) pairs of each surface, in scene order
  std::vector<std::vector<std::array<double, 2>>> explicit_uv;

  // "64x64", "span4", "explicit": the `samples` column of results.
  std::string label() const;
};

inline constexpr int kMaxGridPerDirection = 1 << 16;
inline constexpr int kMaxSpanSteps = 1 << 12;
inline constexpr std::size_t kMaxSamplesPerRequest = std::size_t{1} << 27;

struct SurfaceSamples {
  // tensor: sample (a, b) = (u[a], v[b]) at index a * v.size() + b.
  // not tensor: sample k = (u[k], v[k]).
  bool tensor = true;
  std::vector<double> u, v;

  std::size_t count() const { return tensor ? u.size() * v.size() : u.size(); }
  double u_of(std::size_t k) const { return tensor ? u[k / v.size()] : u[k]; }
  double v_of(std::size_t k) const { return tensor ? v[k % v.size()] : v[k]; }
};

// Grid parameter a of n over [lo, hi]; the last one is exactly hi.
std::vector<double> grid_parameters(double lo, double hi, int n);
// Every non-empty span [k_s, k_s+1] in [knots[degree], knots[count]] split into `steps` equal
// steps, both ends included (a knot shared by two spans appears once per span).
std::vector<double> span_grid_parameters(const std::vector<double>& knots, int degree, int count,
                                         int steps);

// Throws InputError for an impossible sampling (sizes, explicit list shape).
std::vector<SurfaceSamples> sample_parameters(const Scene& scene, const Sampling& sampling);

std::size_t total_samples(const std::vector<SurfaceSamples>& samples);

}  // namespace nurbs
