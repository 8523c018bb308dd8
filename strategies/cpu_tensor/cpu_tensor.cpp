#include "strategies/cpu_tensor/cpu_tensor.h"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <variant>

#include "reference/nurbs_math.h"
#include "strategies/cpu_tensor/row_trim.h"
#include "strategies/cpu_tensor/tensor_kernels.h"
#include "strategies/strategy_options.h"

namespace nurbs {
namespace {

Capabilities tensor_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  // Only the separable samplings: an explicit list has no rows to share basis tables across.
  c.sampling.explicit_list = false;
  c.trims = true;
  return c;
}

std::string simd_description() {
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return "x86-64-v4 (AVX-512) kernels";
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    return "x86-64-v3 (AVX2+FMA) kernels";
#endif
  return "baseline SIMD kernels";
}

// Everything one surface needs at evaluate time, at scalar T.
template <typename T>
struct TensorSurface {
  SurfaceNet<T> net;
  int rows = 0, columns = 0;  // u samples, v samples
  std::vector<T> u_params, v_params;
  std::vector<int> spans_u, spans_v;
  std::vector<T> basis_u, basis_du;  // per u sample, p+1 values each
  std::vector<T> basis_v, basis_dv;  // [l * columns + b]
  std::vector<int> run_begin, run_first;
  explicit TensorSurface(const Surface& s) : net(s) {}
};

// The non-zero basis functions (and first derivatives when asked) at parameter `a` of a list,
// with its knot span: A2.1 + A2.2 / A2.3, once per parameter rather than once per sample.
// `parameter_major`: values at [a * (p+1) + k], else at [k * n + a].
template <typename T>
void basis_entry(int degree, int count, const std::vector<T>& knots, const std::vector<T>& params,
                 std::size_t a, bool derivatives, bool parameter_major, int* spans, T* values,
                 T* ders) {
  const std::size_t n = params.size(), order = static_cast<std::size_t>(degree) + 1;
  const int span = find_span(degree, count, knots.data(), params[a]);
  spans[a] = span;
  T d[3][kMaxOrder];
  if (derivatives)
    basis_function_derivatives(span, params[a], degree, 1, knots.data(), d);
  else
    basis_functions(span, params[a], degree, knots.data(), d[0]);
  for (std::size_t k = 0; k < order; ++k) {
    const std::size_t at = parameter_major ? a * order + k : k * n + a;
    values[at] = d[0][k];
    if (derivatives) ders[at] = d[1][k];
  }
}

template <typename T>
TensorSurface<T> prepare_surface(const Surface& s, const SurfaceSamples& samples, bool normals) {
  TensorSurface<T> t(s);
  t.rows = static_cast<int>(samples.u.size());
  t.columns = static_cast<int>(samples.v.size());
  // Parameters are rounded to T first, as a device holding them in T would (cpu-coxdeboor too).
  t.u_params.assign(samples.u.begin(), samples.u.end());
  t.v_params.assign(samples.v.begin(), samples.v.end());
  const std::size_t order_u = s.degree_u + 1, order_v = s.degree_v + 1;
  t.spans_u.resize(t.rows);
  t.spans_v.resize(t.columns);
  t.basis_u.resize(t.rows * order_u);
  t.basis_v.resize(t.columns * order_v);
  if (normals) {
    t.basis_du.resize(t.rows * order_u);
    t.basis_dv.resize(t.columns * order_v);
  }
  t.run_begin.reserve(t.columns + 1);
  t.run_first.reserve(t.columns);
  return t;
}

// The basis tables of one surface: computed in evaluate() (they are part of the work from
// parameters to points), shared by the calling team of threads.
template <typename T>
void fill_tables_in_team(TensorSurface<T>& t, bool normals) {
  const SurfaceNet<T>& n = t.net;
#pragma omp for schedule(static) nowait
  for (int a = 0; a < t.rows; ++a)
    basis_entry(n.degree_u, n.count_u, n.knots_u, t.u_params, a, normals, true, t.spans_u.data(),
                t.basis_u.data(), t.basis_du.data());
#pragma omp for schedule(static)
  for (int b = 0; b < t.columns; ++b)
    basis_entry(n.degree_v, n.count_v, n.knots_v, t.v_params, b, normals, false, t.spans_v.data(),
                t.basis_v.data(), t.basis_dv.data());
#pragma omp single
  {
    // Runs of consecutive v samples in the same span share their q+1 curve points.
    t.run_begin.clear();
    t.run_first.clear();
    for (int b = 0; b < t.columns; ++b)
      if (b == 0 || t.spans_v[b] != t.spans_v[b - 1]) {
        t.run_begin.push_back(b);
        t.run_first.push_back(t.spans_v[b] - n.degree_v);
      }
    t.run_begin.push_back(t.columns);
  }
}

// extra["simd"]: "on" (default) or "off" (the kernels compiled without vectorisation).
bool simd_option(const StrategyOptions& options) {
  const auto it = options.extra.find("simd");
  if (it == options.extra.end() || it->second.empty() || it->second == "on") return true;
  if (it->second == "off") return false;
  throw std::invalid_argument(
      fmt::format("cpu-tensor option simd = '{}': must be on or off", it->second));
}

class CpuTensor final : public Strategy {
 public:
  explicit CpuTensor(const StrategyOptions& options)
      : threads_(openmp_threads(options)), simd_(simd_option(options)) {}

  std::string_view name() const override { return "cpu-tensor"; }
  Capabilities capabilities() const override { return tensor_capabilities(); }
  DeviceInfo device() const override {
    return {fmt::format("host CPU, {} thread{} (OpenMP)", threads_, threads_ == 1 ? "" : "s"),
            "cpu",
            {{"threads", std::to_string(threads_)},
             {"simd", simd_ ? simd_description()
                            : "off: kernels built with -fno-tree-vectorize (simd=off)"}}};
  }

  void prepare(const Scene& scene, const EvalRequest& request) override {
    refuse_unsupported(name(), capabilities(), scene, request);
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    if (request.precision == Precision::f32)
      prepared_ = prepare_all<float>(scene);
    else
      prepared_ = prepare_all<double>(scene);
    prepare_trims(scene);
  }

  void evaluate() override {
    std::visit([this](auto& p) { evaluate_all(p); }, prepared_);
  }

  // In double whatever the evaluation's precision, on the samples' double parameters: the
  // reference classifies those, and a float-rounded u would move samples across the boundary by
  // more than the band on a domain far from 0.
  bool classify() override {
    const int rows = static_cast<int>(trim_rows_.size());
#pragma omp parallel num_threads(threads_)
    {
      tensor::RowTrimClassifier::Scratch scratch;
      // Dynamic: a row's cost is the number of pieces it meets, uneven across a face.
#pragma omp for schedule(dynamic, 16)
      for (int r = 0; r < rows; ++r) {
        const auto [surface, a] = trim_rows_[r];
        const SurfaceSamples& samples = samples_[surface];
        const std::size_t columns = samples.v.size();
        trims_[surface]->classify_row(samples.u[a], samples.v.data(), columns,
                                      inside_[surface].data() + a * columns, scratch);
      }
    }
    classified_ = true;
    return true;
  }

  EvalResult read_back() override {
    EvalResult out;
    out.surfaces.resize(samples_.size());
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      out.surfaces[i].samples = samples_[i];
      out.surfaces[i].positions = positions_[i];
      out.surfaces[i].normals = normals_[i];
      if (classified_ && trims_[i]) out.surfaces[i].inside = inside_[i];
    }
    return out;
  }

 private:
  template <typename T>
  struct Prepared {
    std::vector<TensorSurface<T>> surfaces;
    std::vector<std::pair<int, int>> rows;        // (surface, u sample): the parallel work items
    std::vector<std::vector<T>> curve, curve_du;  // per thread scratch
    std::vector<std::vector<unsigned char>> unresolved;
  };

  template <typename T>
  Prepared<T> prepare_all(const Scene& scene) {
    Prepared<T> p;
    std::size_t widest = 0, longest_row = 0;
    positions_.assign(scene.surfaces.size(), {});
    normals_.assign(scene.surfaces.size(), {});
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      p.surfaces.push_back(prepare_surface<T>(scene.surfaces[i], samples_[i], request_.normals));
      const TensorSurface<T>& t = p.surfaces.back();
      for (int a = 0; a < t.rows; ++a) p.rows.emplace_back(static_cast<int>(i), a);
      widest = std::max(widest, static_cast<std::size_t>(t.net.count_v) * 4);
      longest_row = std::max(longest_row, static_cast<std::size_t>(t.columns));
      positions_[i] = PointArray(request_.precision, samples_[i].count());
      if (request_.normals) normals_[i] = PointArray(request_.precision, samples_[i].count());
    }
    p.curve.assign(threads_, std::vector<T>(widest));
    if (request_.normals) {
      p.curve_du.assign(threads_, std::vector<T>(widest));
      p.unresolved.assign(threads_, std::vector<unsigned char>(longest_row));
    }
    return p;
  }

  // The row index of every trimmed surface, its mask's storage and the (surface, u sample) rows
  // classify() spreads over the threads.
  void prepare_trims(const Scene& scene) {
    trims_.clear();
    inside_.assign(scene.surfaces.size(), {});
    trim_rows_.clear();
    classified_ = false;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      if (!s.trim) {
        trims_.emplace_back();
        continue;
      }
      if (!std::is_sorted(samples_[i].v.begin(), samples_[i].v.end()))
        throw std::logic_error(
            "cpu-tensor: v samples out of order; the row fill needs them sorted");
      trims_.emplace_back(std::in_place, *s.trim);
      inside_[i].assign(samples_[i].count(), 0);
      for (std::size_t a = 0; a < samples_[i].u.size(); ++a)
        trim_rows_.emplace_back(static_cast<int>(i), a);
    }
  }

  template <typename T>
  static T* data_of(PointArray& a) {
    if constexpr (std::is_same_v<T, float>)
      return a.f32();
    else
      return a.f64();
  }

  template <typename T>
  void evaluate_row(Prepared<T>& p, int surface, int a, int thread) {
    const TensorSurface<T>& t = p.surfaces[surface];
    const T* net = t.net.homogeneous.data()->data();
    const int order_u = t.net.degree_u + 1;
    const bool normals = request_.normals;
    T* curve = p.curve[thread].data();
    T* curve_du = normals ? p.curve_du[thread].data() : nullptr;
    const int first_row = t.spans_u[a] - t.net.degree_u;
    using Contraction = void (*)(const T*, int, int, int, const T*, T*);
    const Contraction contract_rows =
        simd_ ? static_cast<Contraction>(tensor::contract_rows)
              : static_cast<Contraction>(tensor::no_simd::contract_rows);
    contract_rows(net, t.net.count_v, first_row, t.net.degree_u, t.basis_u.data() + a * order_u,
                  curve);
    if (normals)
      contract_rows(net, t.net.count_v, first_row, t.net.degree_u, t.basis_du.data() + a * order_u,
                    curve_du);
    tensor::RowJob<T> job;
    job.curve = curve;
    job.curve_du = curve_du;
    job.run_begin = t.run_begin.data();
    job.run_first = t.run_first.data();
    job.runs = static_cast<int>(t.run_first.size());
    job.degree_v = t.net.degree_v;
    job.count_v_samples = t.columns;
    job.basis_v = t.basis_v.data();
    job.basis_dv = normals ? t.basis_dv.data() : nullptr;
    const std::size_t offset = static_cast<std::size_t>(a) * t.columns * 3;
    job.positions = data_of<T>(positions_[surface]) + offset;
    job.normals = normals ? data_of<T>(normals_[surface]) + offset : nullptr;
    job.unresolved = normals ? p.unresolved[thread].data() : nullptr;
    if (simd_)
      tensor::evaluate_row(job);
    else
      tensor::no_simd::evaluate_row(job);
    if (!normals) return;
    // Collapsed edges and other places where Su x Sv is rounding noise: the reference's own
    // limit-normal rule (nurbs_math.h surface_normal), rare, so scalar.
    for (int b = 0; b < t.columns; ++b) {
      if (!job.unresolved[b]) continue;
      const Vec3<T> n = surface_normal(t.net, t.u_params[a], t.v_params[b]);
      for (int c = 0; c < 3; ++c) job.normals[3 * b + c] = n[c];
    }
  }

  template <typename T>
  void evaluate_all(Prepared<T>& p) {
    const int rows = static_cast<int>(p.rows.size());
#pragma omp parallel num_threads(threads_)
    {
      for (TensorSurface<T>& t : p.surfaces) fill_tables_in_team(t, request_.normals);
#pragma omp for schedule(static)
      for (int r = 0; r < rows; ++r)
        evaluate_row(p, p.rows[r].first, p.rows[r].second, omp_get_thread_num());
    }
  }

  int threads_;
  bool simd_;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::variant<Prepared<float>, Prepared<double>> prepared_;
  std::vector<PointArray> positions_, normals_;
  std::vector<std::optional<tensor::RowTrimClassifier>> trims_;  // per surface
  std::vector<std::vector<std::uint8_t>> inside_;                // per surface, after classify()
  std::vector<std::pair<int, std::size_t>> trim_rows_;           // (surface, u sample)
  bool classified_ = false;
};

}  // namespace

StrategyEntry cpu_tensor_entry() {
  return {"cpu-tensor",
          "tensor-product grid evaluation with per-row/column basis tables (004, Macri 1999), "
          "SIMD across samples, OpenMP across rows",
          "baseline",
          [] {
            return Availability{true, ""};
          },
          tensor_capabilities,
          [](const StrategyOptions& options) -> std::unique_ptr<Strategy> {
            return std::make_unique<CpuTensor>(options);
          }};
}

}  // namespace nurbs
