#include "strategies/cpu_horner/cpu_horner.h"

#include <fmt/format.h>
#include <omp.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <algorithm>
#include <optional>
#include <type_traits>
#include <variant>

#include "reference/nurbs_math.h"
#include "strategies/cpu_horner/power_basis.h"
#include "strategies/strategy_options.h"

namespace nurbs {
namespace {

Capabilities horner_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  // A deforming frame moves control points only: the basis tables stay (004).
  c.updates_control_points = true;
  return c;
}

// One parameter direction: knots, and per non-empty span its origin and (p+1)^2 coefficients.
template <typename T>
struct PowerBasisTable {
  int degree = 0, count = 0;
  std::vector<T> knots;
  std::vector<double> exact_knots;  // as given: forward-difference seeds are formed from them
  horner::Origin origin_rule;
  std::vector<T> origin;  // per span index
  // Per span index, (p+1)^2, see power_basis.h, in the span's own scale: about the span's left
  // knot they multiply ((u - u_s)/h)^j, h = u_{s+1} - u_s, and inverse_width is 1/h (about 0:
  // u^j, Macri's literal form, and 1). Unscaled, the t^j coefficient grows like 1/h^j and
  // overflows float on real models (linkrods.step: degree 10, spans 2.3e-6 wide: 1e56, inf,
  // then inf * 0 = NaN); scaled, every term stays of order one.
  std::vector<T> coefficients;
  std::vector<T> inverse_width;
  // Per span index, the p+1 basis values and derivatives at the span's right knot, rounded once
  // from long double. The span search gives a parameter on an interior knot to the next span
  // (t = 0: the constant coefficients, exact), but the domain's end stays in the last span at
  // t = b - a, where Horner's sum of rounded coefficients misses the exact end basis by ulps --
  // and the neighbouring surface that starts there evaluates the same edge at t = 0: a crack
  // (tests/strategies/shared_edge_test.cpp measured 1e-15 in f64). The end uses these instead.
  std::vector<T> end_values, end_ders;

  PowerBasisTable(const std::vector<double>& k, int p, int n, horner::Origin where)
      : degree(p), count(n), knots(k.begin(), k.end()), exact_knots(k), origin_rule(where) {
    const std::size_t order = static_cast<std::size_t>(p) + 1;
    origin.assign(n, T(0));
    inverse_width.assign(n, T(1));
    coefficients.assign(n * order * order, T(0));
    end_values.assign(n * order, T(0));
    end_ders.assign(n * order, T(0));
    for (int s = p; s < n; ++s) {
      if (!(k[s] < k[s + 1])) continue;
      const long double o = where == horner::Origin::span_start ? k[s] : 0.0L;
      origin[s] = T(o);
      const auto c = horner::power_basis_coefficients(k, p, s, o);
      const long double width =
          where == horner::Origin::span_start ? static_cast<long double>(k[s + 1]) - k[s] : 1.0L;
      inverse_width[s] = T(1.0L / width);
      long double power = 1;  // width^j
      for (std::size_t j = 0; j < order; ++j, power *= width)
        for (std::size_t i = 0; i < order; ++i)
          coefficients[s * order * order + j * order + i] = T(c[j * order + i] * power);
      // About the right knot, the constant and linear coefficients are the value and slope there.
      const auto at_end = horner::power_basis_coefficients(k, p, s, k[s + 1]);
      for (std::size_t i = 0; i < order; ++i) {
        end_values[s * order + i] = T(at_end[i]);
        end_ders[s * order + i] = T(at_end[order + i]);
      }
    }
  }
  // Span search (A2.1), then Horner from the span's coefficients.
  int evaluate(T u, T* values, T* ders) const {
    const int s = find_span(degree, count, knots.data(), u);
    const std::size_t order = static_cast<std::size_t>(degree) + 1;
    if (u == knots[s + 1]) {
      std::copy_n(&end_values[s * order], order, values);
      if (ders) std::copy_n(&end_ders[s * order], order, ders);
      return s;
    }
    horner::horner_basis(coefficients.data() + s * order * order, degree,
                         (u - origin[s]) * inverse_width[s], values, ders);
    if (ders)
      for (std::size_t i = 0; i < order; ++i) ders[i] *= inverse_width[s];
    return s;
  }
};

// How the basis tables at a grid's parameters are built (once per tessellation): Horner at every
// parameter, or Horner at the first p+1 of each span's run of parameters and forward differences
// after (004's alternative, worth it where tessellations change often).
enum class TableMethod { horner, forward_differences };

// The basis at every parameter of one direction of a tensor grid, computed once per tessellation
// (004 "store these in an array ... If at some point we change the number of subdivisions we
// want, we can just recalculate the stored arrays"): per parameter its span and p+1 values (and
// derivatives when normals are asked), so a frame only looks them up. Explicit lists keep the
// per-sample evaluation: their table would be as large as the output and never reused by rows.
template <typename T>
struct SampledBasis {
  int order = 0;
  std::vector<int> span;
  std::vector<T> values, ders;

  SampledBasis(const PowerBasisTable<T>& table, const std::vector<double>& parameters,
               bool with_ders, TableMethod method)
      : order(table.degree + 1), span(parameters.size()) {
    values.resize(parameters.size() * order);
    if (with_ders) ders.resize(values.size());
    const int p = table.degree;
    auto by_horner = [&](std::size_t i) {
      table.evaluate(T(parameters[i]), &values[i * order], with_ders ? &ders[i * order] : nullptr);
    };
    for (std::size_t i = 0; i < parameters.size(); ++i)
      span[i] = find_span(p, table.count, table.knots.data(), T(parameters[i]));
    // Per run of parameters in one span. Forward differences over the run's uniform spacing
    // (from its ends: a grid's parameters are uniform up to their rounding,
    // reference/sampling.h), from the span's exact coefficients (horner::forward_differences). The
    // end of the domain keeps its exact end basis (see PowerBasisTable), so a forward-differenced
    // edge still meets its neighbour.
    for (std::size_t start = 0, end; start < parameters.size(); start = end) {
      for (end = start + 1; end < parameters.size() && span[end] == span[start];) ++end;
      const int run = static_cast<int>(end - start);
      if (method == TableMethod::horner || run <= p + 1) {
        for (std::size_t i = start; i < end; ++i) by_horner(i);
        continue;
      }
      const int s = span[start];
      const long double o =
          table.origin_rule == horner::Origin::span_start ? table.exact_knots[s] : 0.0L;
      const auto c = horner::power_basis_coefficients(table.exact_knots, p, s, o);
      const long double first = parameters[start],
                        step = (static_cast<long double>(parameters[end - 1]) - first) / (run - 1);
      horner::forward_differences(c.data(), p, order, first - o, step, run, &values[start * order]);
      if (with_ders) {
        std::vector<long double> slopes(static_cast<std::size_t>(p) * order);
        for (int j = 0; j < p; ++j)
          for (int k = 0; k < order; ++k) slopes[j * order + k] = (j + 1) * c[(j + 1) * order + k];
        horner::forward_differences(slopes.data(), p - 1, order, first - o, step, run,
                                    &ders[start * order]);
      }
      if (T(parameters[end - 1]) == table.knots[span[end - 1] + 1]) by_horner(end - 1);
    }
  }
  const T* values_at(std::size_t i) const { return &values[i * order]; }
  const T* ders_at(std::size_t i) const { return ders.empty() ? nullptr : &ders[i * order]; }
};

template <typename T>
struct HornerSurface {
  SurfaceNet<T> net;
  PowerBasisTable<T> u, v;
  std::optional<SampledBasis<T>> grid_u, grid_v;  // tensor grids only
  HornerSurface(const Surface& s, horner::Origin where, const SurfaceSamples& samples, bool normals,
                TableMethod method)
      : net(s),
        u(s.knots_u, s.degree_u, s.count_u, where),
        v(s.knots_v, s.degree_v, s.count_v, where) {
    if (!samples.tensor) return;
    grid_u.emplace(u, samples.u, normals, method);
    grid_v.emplace(v, samples.v, normals, method);
  }
};

// 004's TessellateSurfaceSSE keeps the x, y, z, w of a control point in one SSE register and does
// "the same operations to all four at once". Xyzw<T, true> is that register, in intrinsics (float:
// one __m128; double: two __m128d, SSE2 having no four-wide double); Xyzw<T, false> is the plain
// loop the compiler vectorises as it sees fit (the default). Both round the same products and
// sums in the same order, so their results are identical (tests/strategies/cpu_horner).
template <typename T, bool kExplicit>
struct Xyzw {
  Vec4<T> v{};
  static Xyzw load(const Vec4<T>& p) { return {p}; }
  void add_scaled(T s, const Xyzw& x) {
    for (int c = 0; c < 4; ++c) v[c] += s * x.v[c];
  }
  Vec4<T> get() const { return v; }
};
#if defined(__SSE2__)
inline constexpr bool kHaveExplicitSimd = true;
template <>
struct Xyzw<float, true> {
  __m128 v = _mm_setzero_ps();
  static Xyzw load(const Vec4<float>& p) { return {_mm_loadu_ps(p.data())}; }
  void add_scaled(float s, const Xyzw& x) { v = _mm_add_ps(v, _mm_mul_ps(_mm_set1_ps(s), x.v)); }
  Vec4<float> get() const {
    Vec4<float> out;
    _mm_storeu_ps(out.data(), v);
    return out;
  }
};
template <>
struct Xyzw<double, true> {
  __m128d xy = _mm_setzero_pd(), zw = _mm_setzero_pd();
  static Xyzw load(const Vec4<double>& p) {
    return {_mm_loadu_pd(p.data()), _mm_loadu_pd(p.data() + 2)};
  }
  void add_scaled(double s, const Xyzw& x) {
    const __m128d scale = _mm_set1_pd(s);
    xy = _mm_add_pd(xy, _mm_mul_pd(scale, x.xy));
    zw = _mm_add_pd(zw, _mm_mul_pd(scale, x.zw));
  }
  Vec4<double> get() const {
    Vec4<double> out;
    _mm_storeu_pd(out.data(), xy);
    _mm_storeu_pd(out.data() + 2, zw);
    return out;
  }
};
#else
inline constexpr bool kHaveExplicitSimd = false;
#endif

class CpuHorner final : public Strategy {
 public:
  explicit CpuHorner(const StrategyOptions& options) : threads_(openmp_threads(options)) {
    const auto it = options.extra.find("horner-origin");
    if (it != options.extra.end()) {
      if (it->second == "zero")
        origin_ = horner::Origin::zero;
      else if (it->second != "span")
        throw RefusedError(
            fmt::format("horner-origin = '{}': must be 'span' or 'zero'", it->second));
    }
    const auto simd = options.extra.find("horner-simd");
    if (simd != options.extra.end()) {
      if (simd->second == "explicit")
        explicit_simd_ = true;
      else if (simd->second != "auto")
        throw RefusedError(
            fmt::format("horner-simd = '{}': must be 'auto' or 'explicit'", simd->second));
      if (explicit_simd_ && !kHaveExplicitSimd)
        throw RefusedError("horner-simd = 'explicit': this build has no SSE2 (004's path is x86)");
    }
    const auto tables = options.extra.find("horner-tables");
    if (tables != options.extra.end()) {
      if (tables->second == "forward-differences")
        tables_ = TableMethod::forward_differences;
      else if (tables->second != "horner")
        throw RefusedError(fmt::format(
            "horner-tables = '{}': must be 'horner' or 'forward-differences'", tables->second));
    }
  }

  std::string_view name() const override { return "cpu-horner"; }
  Capabilities capabilities() const override { return horner_capabilities(); }
  DeviceInfo device() const override {
    return {fmt::format("host CPU, {} thread{} (OpenMP)", threads_, threads_ == 1 ? "" : "s"),
            "cpu",
            {{"threads", std::to_string(threads_)},
             {"horner-origin", origin_ == horner::Origin::zero ? "zero" : "span"},
             {"horner-simd", explicit_simd_ ? "explicit" : "auto"},
             {"horner-tables", tables_ == TableMethod::horner ? "horner" : "forward-differences"}}};
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    if (request.precision == Precision::f32)
      surfaces_ = make_surfaces<float>(scene, request.normals);
    else
      surfaces_ = make_surfaces<double>(scene, request.normals);
    positions_.resize(scene.surfaces.size());  // kept storage: see PointArray::reset
    normals_.resize(scene.surfaces.size());
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      positions_[i].reset(request.precision, samples_[i].count());
      normals_[i].reset(request.precision, request.normals ? samples_[i].count() : 0);
    }
  }

  void evaluate() override {
    std::visit(
        [this](const auto& s) {
          if (explicit_simd_)
            evaluate_all<true>(s);
          else
            evaluate_all<false>(s);
        },
        surfaces_);
  }

  void update_control_points(const Scene& scene) override {
    std::visit(
        [&](auto& surfaces) {
          using Net = std::remove_reference_t<decltype(surfaces.front().net)>;
          for (std::size_t i = 0; i < surfaces.size(); ++i)
            surfaces[i].net = Net(scene.surfaces[i]);
        },
        surfaces_);
  }

  EvalResult read_back() override {
    EvalResult out;
    read_back_into(out);
    return out;
  }

  // Into out's buffers: same-size copy-assignment and PointArray::reset keep their storage.
  void read_back_into(EvalResult& out) override {
    out.surfaces.resize(samples_.size());
    for (std::size_t i = 0; i < samples_.size(); ++i)
      copy_surface_into(out.surfaces[i], samples_[i], positions_[i], normals_[i]);
  }

 private:
  template <typename T>
  std::vector<HornerSurface<T>> make_surfaces(const Scene& scene, bool normals) const {
    std::vector<HornerSurface<T>> out;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i)
      out.emplace_back(scene.surfaces[i], origin_, samples_[i], normals, tables_);
    return out;
  }

  // One sample: the (p+1)(q+1) homogeneous sums of the point and its two first derivatives, the
  // four coordinates together (004: "do the same operations to all four at once").
  template <typename T, bool kExplicit>
  void evaluate_sample(const HornerSurface<T>& s, int su, const T* nu, const T* dnu, int sv,
                       const T* nv, const T* dnv, T u, T v, std::size_t k, PointArray& positions,
                       PointArray* normals) const {
    using Register = Xyzw<T, kExplicit>;
    const int p = s.net.degree_u, q = s.net.degree_v;
    Register sum, sum_u, sum_v;
    for (int i = 0; i <= p; ++i) {
      Register row, row_v;
      const Vec4<T>* cp = &s.net.at(su - p + i, sv - q);
      for (int l = 0; l <= q; ++l) {
        const Register point = Register::load(cp[l]);
        row.add_scaled(nv[l], point);
        if (normals) row_v.add_scaled(dnv[l], point);
      }
      sum.add_scaled(nu[i], row);
      if (normals) {
        sum_u.add_scaled(dnu[i], row);
        sum_v.add_scaled(nu[i], row_v);
      }
    }
    const Vec4<T> a = sum.get(), au = sum_u.get(), av = sum_v.get();
    const T w = a[3];
    const Vec3<T> point{a[0] / w, a[1] / w, a[2] / w};
    positions.set(k, point);
    if (!normals) return;
    // A4.4 for the first derivatives, then the reference's resolved-normal rule.
    Vec3<T> su_d, sv_d, n;
    for (int c = 0; c < 3; ++c) {
      su_d[c] = (au[c] - au[3] * point[c]) / w;
      sv_d[c] = (av[c] - av[3] * point[c]) / w;
    }
    if (!detail::normalize_if_resolved(cross(su_d, sv_d), su_d, sv_d, n))
      n = surface_normal(s.net, u, v);
    normals->set(k, n);
  }

  template <bool kExplicit, typename T>
  void evaluate_all(const std::vector<HornerSurface<T>>& surfaces) {
    for (std::size_t i = 0; i < surfaces.size(); ++i) {
      const HornerSurface<T>& s = surfaces[i];
      const SurfaceSamples& samples = samples_[i];
      PointArray* normals = request_.normals ? &normals_[i] : nullptr;
      PointArray& positions = positions_[i];
      if (s.grid_u) {
        const std::size_t columns = samples.v.size();
#pragma omp parallel for num_threads(threads_) schedule(static)
        for (std::size_t r = 0; r < samples.u.size(); ++r)
          for (std::size_t b = 0; b < columns; ++b)
            evaluate_sample<T, kExplicit>(
                s, s.grid_u->span[r], s.grid_u->values_at(r), s.grid_u->ders_at(r),
                s.grid_v->span[b], s.grid_v->values_at(b), s.grid_v->ders_at(b), T(samples.u[r]),
                T(samples.v[b]), r * columns + b, positions, normals);
        continue;
      }
#pragma omp parallel for num_threads(threads_) schedule(static)
      for (std::size_t k = 0; k < samples.count(); ++k) {
        T nu[kMaxOrder], dnu[kMaxOrder]{}, nv[kMaxOrder],
            dnv[kMaxOrder]{};  // ders: read only with normals
        const T u = T(samples.u[k]), v = T(samples.v[k]);
        const int su = s.u.evaluate(u, nu, normals ? dnu : nullptr);
        const int sv = s.v.evaluate(v, nv, normals ? dnv : nullptr);
        evaluate_sample<T, kExplicit>(s, su, nu, dnu, sv, nv, dnv, u, v, k, positions, normals);
      }
    }
  }

  int threads_;
  horner::Origin origin_ = horner::Origin::span_start;
  bool explicit_simd_ = false;
  TableMethod tables_ = TableMethod::horner;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::variant<std::vector<HornerSurface<float>>, std::vector<HornerSurface<double>>> surfaces_;
  std::vector<PointArray> positions_, normals_;
};

}  // namespace

StrategyEntry cpu_horner_entry() {
  return host_entry<CpuHorner>(
      {"cpu-horner",
       "Macri 1999 (004): per-span power-basis coefficients, Horner's rule, SIMD over xyzw",
       "baseline", horner_capabilities()});
}

}  // namespace nurbs
