// Surfaces whose domain ends (and knots) are not floats -- ±0.8093981633974483, 1/3, 4/3,
// 1e5 + 1/7 -- and the check that a float strategy's samples there are finite and on the surface
// (issue 28: a parameter rounded outward in float must not give NaN or a point off the surface).
// Shared by the strategy accuracy suite and vk-ksquad's and vk-bezier's tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/surface.h"
#include "strategies/strategy.h"

namespace nurbs::test {

// Degree 3 x 2 on [u0, u1] x [v0, v1], one interior knot per direction at a third, rational.
inline Surface unrepresentable_surface(const std::string& name, double u0, double u1, double v0,
                                       double v1) {
  Surface s;
  s.name = name;
  s.degree_u = 3;
  s.degree_v = 2;
  s.count_u = 5;
  s.count_v = 4;
  const double um = u0 + (u1 - u0) / 3, vm = v0 + (v1 - v0) / 3;
  s.knots_u = {u0, u0, u0, u0, um, u1, u1, u1, u1};
  s.knots_v = {v0, v0, v0, vm, v1, v1, v1};
  for (int i = 0; i < s.count_u; ++i)
    for (int j = 0; j < s.count_v; ++j) {
      s.points.push_back({0.5 * i, 0.4 * j, 0.3 * std::sin(1.3 * i + 0.7 * j)});
      s.weights.push_back(1.0 + 0.25 * ((i + 2 * j) % 3));
    }
  return s;
}

inline Scene unrepresentable_ends_scene() {
  Scene scene;
  scene.name = "unrepresentable-ends";
  const double a = 0.8093981633974483;  // linkrods.step's domain, to double precision
  scene.surfaces.push_back(unrepresentable_surface("pm-a", -a, a, 1.0 / 3, 4.0 / 3));
  scene.surfaces.push_back(
      unrepresentable_surface("1e5", 1e5 + 1.0 / 7, 1e5 + 4.0 / 7, -a, 1.0 / 3));
  return scene;
}

// Every sample of `result` finite and within `ulps` float ulps of the scene's largest coordinate
// of the reference at the parameter the strategy evaluated -- the returned one (a float's exact
// value) -- clamped into the surface's domain, as the reference's span search (A2.1) does; plus,
// where the float parameter lies outside the domain, what the surface's own slope over that
// distance allows (a strategy that evaluates the end span's polynomial there moves that far).
// A surface whose knots move by more than 1e-4 of its shortest span when rounded to float (the
// 1e5 + 1/7 one: 0.004 of 0.14) is another surface in float everywhere, not only at its ends --
// no float-knot strategy meets the reference there -- so only finiteness is asserted for it.
// Returns the samples whose position was checked.
inline bool float_knots_hold(const Surface& s) {
  double shift = 0, shortest = 1e300;
  for (const std::vector<double>* k : {&s.knots_u, &s.knots_v})
    for (std::size_t i = 0; i < k->size(); ++i) {
      shift = std::max(shift, std::abs(static_cast<float>((*k)[i]) - (*k)[i]));
      if (i + 1 < k->size() && (*k)[i] < (*k)[i + 1])
        shortest = std::min(shortest, (*k)[i + 1] - (*k)[i]);
    }
  return shift <= 1e-4 * shortest;
}

inline std::size_t expect_on_surface(const Scene& scene, const EvalResult& result, double ulps,
                                     const std::string& label) {
  double largest = 0;
  for (const Surface& s : scene.surfaces)
    for (const auto& p : s.points)
      for (double x : p) largest = std::max(largest, std::abs(x));
  std::size_t checked = 0;
  EXPECT_EQ(result.surfaces.size(), scene.surfaces.size()) << label;
  for (std::size_t i = 0; i < result.surfaces.size() && i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    const SurfaceNet<double> net(s);
    const SurfaceResult& r = result.surfaces[i];
    const std::size_t nv = r.samples.tensor ? r.samples.v.size() : 1;
    for (std::size_t k = 0; k < r.samples.count(); ++k) {
      const double u_requested = r.samples.tensor ? r.samples.u[k / nv] : r.samples.u[k];
      const double v_requested = r.samples.tensor ? r.samples.v[k % nv] : r.samples.v[k];
      // the device evaluates at the float rounding (exact when the strategy returned it)
      const double u = static_cast<float>(u_requested), v = static_cast<float>(v_requested);
      const double uc = std::clamp(u, s.u_min(), s.u_max()),
                   vc = std::clamp(v, s.v_min(), s.v_max());
      const Vec3<double> ref = surface_point(net, uc, vc);
      // the slope at the end, by a difference over 1e-4 of the domain inward
      const double hu = 1e-4 * (s.u_max() - s.u_min()), hv = 1e-4 * (s.v_max() - s.v_min());
      const Vec3<double> pu = surface_point(net, uc == s.u_max() ? uc - hu : uc + hu, vc);
      const Vec3<double> pv = surface_point(net, uc, vc == s.v_max() ? vc - hv : vc + hv);
      const double outside = norm(Vec3<double>{pu[0] - ref[0], pu[1] - ref[1], pu[2] - ref[2]}) /
                                 hu * std::abs(u - uc) +
                             norm(Vec3<double>{pv[0] - ref[0], pv[1] - ref[1], pv[2] - ref[2]}) /
                                 hv * std::abs(v - vc);
      const double bound = ulps * FLT_EPSILON / 2 * largest + 2 * outside;
      const float* p = r.positions.f32() + 3 * k;
      const double d = std::hypot(p[0] - ref[0], p[1] - ref[1], p[2] - ref[2]);
      EXPECT_TRUE(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]))
          << label << " surface " << i << " (" << u << ", " << v << ")";
      if (!float_knots_hold(s)) continue;
      ++checked;
      EXPECT_LE(d, bound) << label << " surface " << i << " (" << u << ", " << v << ")";
    }
  }
  return checked;
}

}  // namespace nurbs::test
