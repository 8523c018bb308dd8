#include "reference/reference_evaluator.h"

#include <stdexcept>

#include "reference/nurbs_math.h"
#include "reference/trim_classify.h"
#include "reference/tspline.h"

namespace nurbs {

bool parse_reference_precision(std::string_view text, ReferencePrecision& out) {
  if (text == "long-double") {
    out = ReferencePrecision::long_double;
    return true;
  }
  if (text == "float128" && NURBSBENCH_HAS_FLOAT128) {
    out = ReferencePrecision::float128;
    return true;
  }
  return false;
}

std::string_view to_string(ReferencePrecision p) {
  return p == ReferencePrecision::long_double ? "long-double" : "float128";
}

namespace {

template <typename T>
Point3 to_point(const Vec3<T>& p) {
  return {static_cast<double>(p[0]), static_cast<double>(p[1]), static_cast<double>(p[2])};
}

// Basis rows of a parameter list, computed once per parameter (a grid has NU + NV of them, not
// NU * NV).
template <typename T>
struct BasisRows {
  std::vector<int> spans;
  std::vector<T> values;  // (degree+1) per parameter
  BasisRows(const std::vector<double>& params, int degree, int count, const std::vector<T>& knots)
      : spans(params.size()), values(params.size() * (degree + 1)) {
    for (std::size_t a = 0; a < params.size(); ++a) {
      const T t = T(params[a]);
      spans[a] = find_span(degree, count, knots.data(), t);
      basis_functions(spans[a], t, degree, knots.data(), &values[a * (degree + 1)]);
    }
  }
};

template <typename T>
ReferenceSurface evaluate_surface(const Surface& surface, const SurfaceSamples& samples,
                                  bool with_normals) {
  const SurfaceNet<T> net(surface);
  ReferenceSurface out;
  const std::size_t n = samples.count();
  out.positions.resize(n);
  if (samples.tensor) {
    const BasisRows<T> rows_u(samples.u, net.degree_u, net.count_u, net.knots_u);
    const BasisRows<T> rows_v(samples.v, net.degree_v, net.count_v, net.knots_v);
    const std::size_t nu = samples.u.size(), nv = samples.v.size();
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < nu; ++a)
      for (std::size_t b = 0; b < nv; ++b)
        out.positions[a * nv + b] = to_point(
            surface_point_from_basis(net, rows_u.spans[a], &rows_u.values[a * (net.degree_u + 1)],
                                     rows_v.spans[b], &rows_v.values[b * (net.degree_v + 1)]));
  } else {
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k)
      out.positions[k] = to_point(surface_point(net, T(samples.u[k]), T(samples.v[k])));
  }
  if (with_normals) {
    out.normals.resize(n);
#pragma omp parallel for schedule(static)
    for (std::size_t k = 0; k < n; ++k)
      out.normals[k] = to_point(surface_normal(net, T(samples.u_of(k)), T(samples.v_of(k))));
    if (surface.reversed)
      for (Point3& normal : out.normals)
        for (double& c : normal) c = -c;
  }
  if (surface.trim) {
    TrimClassification trim = classify_trim_samples(*surface.trim, samples, /*with_distance=*/true,
                                                    TrimScalar::long_double);
    out.inside = std::move(trim.inside);
    out.trim_distance = std::move(trim.distance);
  }
  return out;
}

template <typename T>
std::vector<ReferenceSurface> evaluate_all(const Scene& scene,
                                           const std::vector<SurfaceSamples>& samples,
                                           bool with_normals, ReferencePrecision precision) {
  std::vector<ReferenceSurface> out;
  out.reserve(scene.surfaces.size());
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const Surface& s = scene.surfaces[i];
    if (s.is_tspline())
      out.push_back(evaluate_tspline_reference(*s.tspline, TSplineInfluence(*s.tspline, s.name),
                                               samples[i], with_normals, precision));
    else
      out.push_back(evaluate_surface<T>(s, samples[i], with_normals));
  }
  return out;
}

}  // namespace

std::vector<ReferenceSurface> evaluate_reference(const Scene& scene,
                                                 const std::vector<SurfaceSamples>& samples,
                                                 bool with_normals, ReferencePrecision precision) {
  if (samples.size() != scene.surfaces.size())
    throw std::invalid_argument("evaluate_reference: one SurfaceSamples per surface needed");
  return with_reference_scalar(precision, [&]<typename T>() {
    return evaluate_all<T>(scene, samples, with_normals, precision);
  });
}

}  // namespace nurbs
