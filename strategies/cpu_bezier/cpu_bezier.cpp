#include "strategies/cpu_bezier/cpu_bezier.h"

#include <fmt/format.h>
#include <omp.h>

#include <stdexcept>
#include <variant>

#include "reference/bezier_decomposition.h"
#include "reference/nurbs_math.h"
#include "strategies/strategy_options.h"

namespace nurbs {
namespace {

Capabilities bezier_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  c.updates_control_points = true;
  return c;
}

// The Bernstein polynomials of one parameter. Why A1.3 AllBernstein plus a (p+1)(q+1) sum rather
// than de Casteljau on the control points: the triangle of A1.3 is de Casteljau's scheme run on
// the basis instead of the points -- the same convex combinations of non-negative numbers, so the
// same stability -- but it costs O(p^2) once per parameter (shared by a whole row or column of a
// grid) and then O(pq) per sample, where surface de Casteljau costs O(p^2 q + q^2) four-vectors
// per sample. Derivatives (for normals) come from the degree p-1 row of the same triangle:
// dB_{i,p}/dt = p (B_{i-1,p-1} - B_{i,p-1}) (The NURBS Book ch. 1, Bernstein derivatives).
template <typename T>
struct AxisSample {
  int segment = 0;
  T basis[kMaxOrder];
  T derivative[kMaxOrder];  // d/du (chain rule through the segment's length), when asked
};

template <typename T>
void all_bernstein(int n, T t, T* b) {  // A1.3 AllBernstein
  b[0] = T(1);
  const T t1 = T(1) - t;
  for (int j = 1; j <= n; ++j) {
    T saved = T(0);
    for (int k = 0; k < j; ++k) {
      const T temp = b[k];
      b[k] = saved + t1 * temp;
      saved = t * temp;
    }
    b[j] = saved;
  }
}

// Locates the patch of parameter u the way every strategy does (A2.1 span search on the knots
// rounded to T, the end parameter in the last non-empty span), then the local parameter of the
// segment and its Bernstein values.
template <typename T>
void axis_sample(const std::vector<T>& knots, int degree, int count,
                 const std::vector<int>& segment_of_span, T u, bool derivatives,
                 AxisSample<T>& out) {
  const int span = find_span(degree, count, knots.data(), u);
  out.segment = segment_of_span[span];
  const T a = knots[span], length = knots[span + 1] - a;
  const T t = (u - a) / length;
  if (!derivatives) {
    all_bernstein(degree, t, out.basis);
    return;
  }
  T lower[kMaxOrder];
  all_bernstein(degree - 1, t, lower);
  const T t1 = T(1) - t, scale = T(degree) / length;
  T saved = T(0);
  for (int k = 0; k < degree; ++k) {
    out.basis[k] = saved + t1 * lower[k];
    saved = t * lower[k];
  }
  out.basis[degree] = saved;
  for (int k = 0; k <= degree; ++k)
    out.derivative[k] = scale * ((k > 0 ? lower[k - 1] : T(0)) - (k < degree ? lower[k] : T(0)));
}

// Everything one surface needs. The decomposition runs in double whatever the evaluation
// precision, as a CPU converter holding the model in double would (003 Fig. 3(a)), and each
// patch is handed to the evaluator relative to its own origin (its first control point, rounded
// to T): the Bézier form is affine invariant, so S = O + sum B w (P - O) / sum B w exactly.
// Without it, float patches far from the origin lose their derivatives: knot insertion packs the
// Bézier points closely, and their float rounding at |x| = 1e4 (far-origin) tilted normals by
// 1.35 degrees (cpu-coxdeboor: 0.15), although positions stayed within 3 ulps.
template <typename T>
struct BezierSurface {
  SurfaceNet<T> net;          // knots in T for the span search; the limit-normal fallback
  SurfaceNet<double> source;  // the decomposition's input
  BezierPatches<double> decomposed;
  DecompositionScratch<double> scratch;
  BezierPatches<T> patches;      // what evaluate() reads, relative to `origins`
  std::vector<Vec3<T>> origins;  // one per patch
  std::vector<int> segment_of_span_u, segment_of_span_v;
  std::vector<T> u_params, v_params;
  std::vector<AxisSample<T>> u_table, v_table;  // tensor samplings: one entry per u / v sample
  explicit BezierSurface(const Surface& s) : net(s), source(s) {}

  // A5.7 on the current control points, then the patches in T about their origins.
  void decompose() {
    decompose_surface(source, decomposed, scratch);
    patches.degree_u = decomposed.degree_u;
    patches.degree_v = decomposed.degree_v;
    patches.segments_u = decomposed.segments_u;
    patches.segments_v = decomposed.segments_v;
    patches.spans_u = decomposed.spans_u;
    patches.spans_v = decomposed.spans_v;
    patches.breaks_u.assign(decomposed.breaks_u.begin(), decomposed.breaks_u.end());
    patches.breaks_v.assign(decomposed.breaks_v.begin(), decomposed.breaks_v.end());
    patches.points.resize(decomposed.points.size());
    origins.resize(decomposed.patch_count());
    const std::size_t per_patch = decomposed.points_per_patch();
    for (std::size_t g = 0; g < origins.size(); ++g) {
      const Vec4<double>* from = decomposed.points.data() + g * per_patch;
      Vec4<T>* to = patches.points.data() + g * per_patch;
      Vec3<T>& o = origins[g];
      for (int c = 0; c < 3; ++c) o[c] = T(from[0][c] / from[0][3]);
      for (std::size_t k = 0; k < per_patch; ++k) {
        const double w = from[k][3];
        for (int c = 0; c < 3; ++c) to[k][c] = T(from[k][c] - double(o[c]) * w);
        to[k][3] = T(w);
      }
    }
    segment_of_span_u.assign(net.count_u, 0);
    segment_of_span_v.assign(net.count_v, 0);
    for (int g = 0; g < patches.segments_u; ++g) segment_of_span_u[patches.spans_u[g]] = g;
    for (int h = 0; h < patches.segments_v; ++h) segment_of_span_v[patches.spans_v[h]] = h;
  }
  void sample_u(T u, bool derivatives, AxisSample<T>& out) const {
    axis_sample(net.knots_u, net.degree_u, net.count_u, segment_of_span_u, u, derivatives, out);
  }
  void sample_v(T v, bool derivatives, AxisSample<T>& out) const {
    axis_sample(net.knots_v, net.degree_v, net.count_v, segment_of_span_v, v, derivatives, out);
  }
};

// The rational Bézier patch at one sample: the homogeneous sum (003 Eq. (2)), the divide, the
// patch origin added back, and with normals the quotient rule S_u = (A_u - w_u S) / w.
template <typename T>
void patch_point(const BezierSurface<T>& s, const AxisSample<T>& su, const AxisSample<T>& sv, T u,
                 T v, bool normals, T* position, T* normal) {
  const int p = s.patches.degree_u, q = s.patches.degree_v;
  const Vec4<T>* pts = s.patches.patch(su.segment, sv.segment);
  const Vec3<T>& origin =
      s.origins[static_cast<std::size_t>(su.segment) * s.patches.segments_v + sv.segment];
  Vec4<T> sum{}, sum_u{}, sum_v{};
  for (int k = 0; k <= p; ++k) {
    Vec4<T> row{}, row_v{};
    for (int l = 0; l <= q; ++l) {
      const Vec4<T>& pt = pts[k * (q + 1) + l];
      for (int c = 0; c < 4; ++c) row[c] += sv.basis[l] * pt[c];
      if (normals)
        for (int c = 0; c < 4; ++c) row_v[c] += sv.derivative[l] * pt[c];
    }
    for (int c = 0; c < 4; ++c) sum[c] += su.basis[k] * row[c];
    if (normals) {
      for (int c = 0; c < 4; ++c) sum_u[c] += su.derivative[k] * row[c];
      for (int c = 0; c < 4; ++c) sum_v[c] += su.basis[k] * row_v[c];
    }
  }
  const Vec3<T> point{sum[0] / sum[3], sum[1] / sum[3], sum[2] / sum[3]};  // about the origin
  for (int c = 0; c < 3; ++c) position[c] = origin[c] + point[c];
  if (!normals) return;
  Vec3<T> du, dv;
  for (int c = 0; c < 3; ++c) {
    du[c] = (sum_u[c] - sum_u[3] * point[c]) / sum[3];
    dv[c] = (sum_v[c] - sum_v[3] * point[c]) / sum[3];
  }
  Vec3<T> n;
  // Where Su x Sv is rounding noise (collapsed edges) the reference's limit-normal rule on the
  // NURBS net, as cpu-tensor does: rare, and the same answer the reference gives.
  if (!detail::normalize_if_resolved(cross(du, dv), du, dv, n)) n = surface_normal(s.net, u, v);
  for (int c = 0; c < 3; ++c) normal[c] = n[c];
}

class CpuBezier final : public Strategy {
 public:
  explicit CpuBezier(const StrategyOptions& options) : threads_(openmp_threads(options)) {}

  std::string_view name() const override { return "cpu-bezier"; }
  Capabilities capabilities() const override { return bezier_capabilities(); }
  DeviceInfo device() const override {
    return {fmt::format("host CPU, {} thread{} (OpenMP evaluation, serial decomposition)", threads_,
                        threads_ == 1 ? "" : "s"),
            "cpu",
            {{"threads", std::to_string(threads_)}}};
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    if (request.precision == Precision::f32)
      surfaces_ = prepare_all<float>(scene);
    else
      surfaces_ = prepare_all<double>(scene);
  }

  // 003 §2 / Fig. 3(a): the Bézier form must be rebuilt from the moved NURBS control points --
  // the full decomposition of every surface, every frame.
  void update_control_points(const Scene& scene) override {
    std::visit([&](auto& surfaces) { update_all(surfaces, scene); }, surfaces_);
  }

  void evaluate() override {
    std::visit([this](auto& surfaces) { evaluate_all(surfaces); }, surfaces_);
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
  std::vector<BezierSurface<T>> prepare_all(const Scene& scene) {
    std::vector<BezierSurface<T>> surfaces;
    surfaces.reserve(scene.surfaces.size());
    positions_.resize(scene.surfaces.size());  // kept storage: see PointArray::reset
    normals_.resize(scene.surfaces.size());
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      BezierSurface<T>& s = surfaces.emplace_back(scene.surfaces[i]);
      s.decompose();
      // Parameters rounded to T first, as a device holding them in T would (like the others).
      s.u_params.assign(samples_[i].u.begin(), samples_[i].u.end());
      s.v_params.assign(samples_[i].v.begin(), samples_[i].v.end());
      if (samples_[i].tensor) {
        s.u_table.resize(s.u_params.size());
        s.v_table.resize(s.v_params.size());
      }
      positions_[i].reset(request_.precision, samples_[i].count());
      normals_[i].reset(request_.precision, request_.normals ? samples_[i].count() : 0);
    }
    return surfaces;
  }

  template <typename T>
  static void update_all(std::vector<BezierSurface<T>>& surfaces, const Scene& scene) {
    if (scene.surfaces.size() != surfaces.size())
      throw std::invalid_argument(
          fmt::format("cpu-bezier: update_control_points with {} surfaces, prepared with {}",
                      scene.surfaces.size(), surfaces.size()));
    for (std::size_t i = 0; i < surfaces.size(); ++i) {
      const Surface& in = scene.surfaces[i];
      SurfaceNet<T>& net = surfaces[i].net;
      const SurfaceNet<double>& source = surfaces[i].source;
      if (in.count_u != net.count_u || in.count_v != net.count_v || in.degree_u != net.degree_u ||
          in.degree_v != net.degree_v || in.knots_u != source.knots_u ||
          in.knots_v != source.knots_v)
        throw std::invalid_argument(
            fmt::format("cpu-bezier: update_control_points: surface '{}' changed its degrees, "
                        "counts or knots (only points and weights may move)",
                        in.name));
      for (std::size_t k = 0; k < in.points.size(); ++k) {
        const double w = in.weights[k];
        const Vec4<double> h{in.points[k][0] * w, in.points[k][1] * w, in.points[k][2] * w, w};
        surfaces[i].source.homogeneous[k] = h;
        const T wt = T(w);  // as SurfaceNet<T> forms it
        net.homogeneous[k] = {T(in.points[k][0]) * wt, T(in.points[k][1]) * wt,
                              T(in.points[k][2]) * wt, wt};
      }
      surfaces[i].decompose();
    }
  }

  template <typename T>
  void evaluate_all(std::vector<BezierSurface<T>>& surfaces) {
    const bool normals = request_.normals;
    for (std::size_t i = 0; i < surfaces.size(); ++i) {
      BezierSurface<T>& s = surfaces[i];
      T* positions = positions_[i].template data<T>();
      T* normal_out = normals ? normals_[i].template data<T>() : nullptr;
      const int rows = static_cast<int>(s.u_params.size());
      if (samples_[i].tensor) {
        // Grid and span grid are tensor products: one patch location and one Bernstein row per
        // u sample and per v sample (the separation docs/design.md §Sampling allows), then per
        // sample the patch's homogeneous sum.
        const int columns = static_cast<int>(s.v_params.size());
#pragma omp parallel num_threads(threads_)
        {
#pragma omp for schedule(static) nowait
          for (int a = 0; a < rows; ++a) s.sample_u(s.u_params[a], normals, s.u_table[a]);
#pragma omp for schedule(static)
          for (int b = 0; b < columns; ++b) s.sample_v(s.v_params[b], normals, s.v_table[b]);
#pragma omp for schedule(static)
          for (int a = 0; a < rows; ++a)
            for (int b = 0; b < columns; ++b) {
              const std::size_t k = static_cast<std::size_t>(a) * columns + b;
              patch_point(s, s.u_table[a], s.v_table[b], s.u_params[a], s.v_params[b], normals,
                          positions + 3 * k, normals ? normal_out + 3 * k : nullptr);
            }
        }
      } else {
#pragma omp parallel for schedule(static) num_threads(threads_)
        for (int k = 0; k < rows; ++k) {
          AxisSample<T> su, sv;
          s.sample_u(s.u_params[k], normals, su);
          s.sample_v(s.v_params[k], normals, sv);
          patch_point(s, su, sv, s.u_params[k], s.v_params[k], normals, positions + 3 * k,
                      normals ? normal_out + 3 * k : nullptr);
        }
      }
    }
  }

  int threads_;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::variant<std::vector<BezierSurface<float>>, std::vector<BezierSurface<double>>> surfaces_;
  std::vector<PointArray> positions_, normals_;
};

}  // namespace

StrategyEntry cpu_bezier_entry() {
  return host_entry<CpuBezier>(
      {"cpu-bezier",
       "NURBS to rational Bezier decomposition (The NURBS Book A5.6/A5.7), then Bezier "
       "evaluation: the baseline of 003 §2 (RPNS 2014)",
       "baseline", bezier_capabilities()});
}

}  // namespace nurbs
