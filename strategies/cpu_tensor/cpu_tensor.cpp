#include "strategies/cpu_tensor/cpu_tensor.h"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>
#include <variant>

#include "reference/nurbs_math.h"
#include "strategies/aligned_vector.h"
#include "strategies/cpu_tensor/row_trim.h"
#include "strategies/cpu_tensor/streaming_store.h"
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

// The basis table of one parameter list of one knot vector: its spans and the non-zero basis
// functions (and first derivatives when normals are asked) at every parameter, computed in
// evaluate() (they are part of the work from parameters to points). Surfaces whose knot vector,
// degree and parameters along that direction are identical share one table (many-N's Bezier
// patches, a model's faces sampled alike), so a scene of many small faces pays for its distinct
// tables, not for one per face.
template <typename T>
struct AxisTable {
  int degree = 0, count = 0;
  std::vector<T> knots, params;
  // u tables: values at [a * (p+1) + k], one sample's functions together (a row reads one);
  // v tables: at [k * n + b], the sample loop of a row reads each k contiguously.
  bool parameter_major = false;
  std::vector<int> spans;
  std::vector<T> basis, ders;
  // v tables: runs of consecutive samples in the same span, which share their q+1 curve points.
  std::vector<int> run_begin, run_first;
};

// A piece of one table's parameters: the unit the threads share the table work in.
struct TableChunk {
  int table = 0, begin = 0, end = 0;
};

// Chunks small enough that one large grid's tables spread over the threads, large enough that a
// chunk's cost dwarfs taking it from the shared counter.
inline constexpr int kTableChunk = 256;

// Everything one surface needs at evaluate time, at scalar T.
template <typename T>
struct TensorSurface {
  SurfaceNet<T> net;
  int rows = 0, columns = 0;  // u samples, v samples
  int table_u = 0, table_v = 0;
  bool rational = true;
  explicit TensorSurface(const Surface& s)
      : net(s),
        rational(
            std::any_of(s.weights.begin(), s.weights.end(), [](double w) { return w != 1.0; })) {}
};

// The index of the table for (degree, knots, parameters) in `tables`, added when no table there
// has them; `index` maps a hash of the three to the tables that have it.
template <typename T>
int find_or_add_table(std::vector<AxisTable<T>>& tables,
                      std::unordered_multimap<std::size_t, int>& index, int degree,
                      const std::vector<T>& knots, const std::vector<double>& samples,
                      bool parameter_major, bool derivatives) {
  // Parameters are rounded to T first, as a device holding them in T would (cpu-coxdeboor too).
  const std::vector<T> params(samples.begin(), samples.end());
  std::size_t hash = std::hash<int>()(degree * 2 + (parameter_major ? 1 : 0));
  const auto mix = [&hash](T x) { hash = hash * 1000003u ^ std::hash<T>()(x); };
  for (T k : knots) mix(k);
  for (T u : params) mix(u);
  const auto [first, last] = index.equal_range(hash);
  for (auto it = first; it != last; ++it) {
    const AxisTable<T>& t = tables[it->second];
    if (t.degree == degree && t.parameter_major == parameter_major && t.knots == knots &&
        t.params == params)
      return it->second;
  }
  AxisTable<T> t;
  t.degree = degree;
  t.count = static_cast<int>(knots.size()) - degree - 1;
  t.knots = knots;
  t.params = params;
  t.parameter_major = parameter_major;
  const std::size_t n = params.size(), order = static_cast<std::size_t>(degree) + 1;
  t.spans.resize(n);
  t.basis.resize(n * order);
  if (derivatives) t.ders.resize(n * order);
  if (!parameter_major) {
    t.run_begin.reserve(n + 1);
    t.run_first.reserve(n);
  }
  tables.push_back(std::move(t));
  index.emplace(hash, static_cast<int>(tables.size()) - 1);
  return static_cast<int>(tables.size()) - 1;
}

// Spans and basis functions of the parameters [begin, end) of `t`: A2.1 + A2.2 / A2.3, once per
// parameter rather than once per sample.
template <typename T>
void fill_table_chunk(AxisTable<T>& t, int begin, int end, bool derivatives) {
  const std::size_t n = t.params.size(), order = static_cast<std::size_t>(t.degree) + 1;
  for (int a = begin; a < end; ++a) {
    const T u = t.params[a];
    const int span = find_span(t.degree, t.count, t.knots.data(), u);
    t.spans[a] = span;
    T d[3][kMaxOrder];
    if (derivatives)
      basis_function_derivatives(span, u, t.degree, 1, t.knots.data(), d);
    else
      basis_functions(span, u, t.degree, t.knots.data(), d[0]);
    for (std::size_t k = 0; k < order; ++k) {
      const std::size_t at = t.parameter_major ? a * order + k : k * n + a;
      t.basis[at] = d[0][k];
      if (derivatives) t.ders[at] = d[1][k];
    }
  }
}

// The runs of a v table, from its spans (after every chunk of it is filled).
template <typename T>
void find_runs(AxisTable<T>& t) {
  t.run_begin.clear();
  t.run_first.clear();
  const int n = static_cast<int>(t.spans.size());
  for (int b = 0; b < n; ++b)
    if (b == 0 || t.spans[b] != t.spans[b - 1]) {
      t.run_begin.push_back(b);
      t.run_first.push_back(t.spans[b] - t.degree);
    }
  t.run_begin.push_back(n);
}

// Whether any of n flags (RowJob::unresolved: T(0) or T(1)) is set: an OR over their bits (0.0
// is all zero bits), which vectorises, so a row with none set (almost every row) skips the
// per-sample scan; that scan, a scalar compare per sample, was a tenth of evaluate()'s time with
// normals on patch144 at 4096^2 (perf).
template <typename T>
bool any_flagged(const T* flags, int n) {
  using Bits = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
  Bits any = 0;
  for (int b = 0; b < n; ++b) {
    Bits bits;
    std::memcpy(&bits, flags + b, sizeof bits);
    any |= bits;
  }
  return any != 0;
}

// Whether extra[key] picks `other` rather than `usual` (its default, also when empty); any other
// value is refused, naming both.
bool picks_other(const StrategyOptions& options, const std::string& key, std::string_view usual,
                 std::string_view other) {
  const auto it = options.extra.find(key);
  if (it == options.extra.end() || it->second.empty() || it->second == usual) return false;
  if (it->second == other) return true;
  throw std::invalid_argument(
      fmt::format("cpu-tensor option {} = '{}': must be {} or {}", key, it->second, usual, other));
}

// extra["simd"]: "on" (default) or "off" (the kernels compiled without vectorisation).
bool simd_option(const StrategyOptions& options) {
  return !picks_other(options, "simd", "on", "off");
}

// extra["stores"]: how rows reach the result. "cached" (default): ordinary stores; "streaming":
// each row finished in a per-thread staging buffer, then copied out with non-temporal stores
// (no read-for-ownership). Streaming is not the default because it lost where it was measured:
// on the 2-core EPYC guest, patch144 4096^2 f32 reached 0.42 of the store limit streaming against
// 0.67 cached, many-4096 at 64^2 0.35 against 0.47 (nurbsbench_gbench store-limit cases, one
// process); the option stays so other machines can measure it.
bool streaming_option(const StrategyOptions& options) {
  return picks_other(options, "stores", "cached", "streaming");
}

class CpuTensor final : public Strategy {
 public:
  explicit CpuTensor(const StrategyOptions& options)
      : threads_(openmp_threads(options)),
        simd_(simd_option(options)),
        streaming_(streaming_option(options)) {}

  std::string_view name() const override { return "cpu-tensor"; }
  Capabilities capabilities() const override { return tensor_capabilities(); }
  DeviceInfo device() const override {
    return {fmt::format("host CPU, {} thread{} (OpenMP)", threads_, threads_ == 1 ? "" : "s"),
            "cpu",
            {{"threads", std::to_string(threads_)},
             {"simd", simd_ ? simd_description()
                            : "off: kernels built with -fno-tree-vectorize (simd=off)"},
             {"stores", streaming_ ? "streaming (stores=streaming)" : "cached"}}};
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
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
    read_back_into(out);
    return out;
  }

  // Copy-assignment into out's vectors of the same size reuses their storage.
  void read_back_into(EvalResult& out) override {
    out.surfaces.resize(samples_.size());
    for (std::size_t i = 0; i < samples_.size(); ++i)
      copy_surface_into(out.surfaces[i], samples_[i], positions_[i], normals_[i],
                        classified_ && trims_[i] ? &inside_[i] : nullptr);
  }

 private:
  template <typename T>
  struct Prepared {
    std::vector<TensorSurface<T>> surfaces;
    std::vector<AxisTable<T>> tables;       // shared by the surfaces that index them
    std::vector<TableChunk> table_chunks;   // the table work, over every table
    std::vector<int> v_tables;              // the tables whose runs a row reads
    std::vector<std::pair<int, int>> rows;  // (surface, u sample): the parallel work items
    // Per thread, each on cache lines of its own (AlignedVector: no false sharing between threads).
    std::vector<AlignedVector<T>> curve, curve_du;                   // scratch
    std::vector<AlignedVector<T>> unresolved;                        // RowJob::unresolved
    std::vector<AlignedVector<T>> staged_positions, staged_normals;  // when streaming
  };

  template <typename T>
  Prepared<T> prepare_all(const Scene& scene) {
    Prepared<T> p;
    std::size_t widest = 0, longest_row = 0;
    // Resized, not reassigned: a prepare() of the same request keeps the output buffers (and their
    // mapped pages) of the last one.
    positions_.resize(scene.surfaces.size());
    normals_.resize(scene.surfaces.size());
    std::unordered_multimap<std::size_t, int> index;
    p.surfaces.reserve(scene.surfaces.size());
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      TensorSurface<T>& t = p.surfaces.emplace_back(scene.surfaces[i]);
      t.rows = static_cast<int>(samples_[i].u.size());
      t.columns = static_cast<int>(samples_[i].v.size());
      t.table_u = find_or_add_table(p.tables, index, t.net.degree_u, t.net.knots_u, samples_[i].u,
                                    true, request_.normals);
      t.table_v = find_or_add_table(p.tables, index, t.net.degree_v, t.net.knots_v, samples_[i].v,
                                    false, request_.normals);
      for (int a = 0; a < t.rows; ++a) p.rows.emplace_back(static_cast<int>(i), a);
      widest = std::max(widest, static_cast<std::size_t>(t.net.count_v) * 4);
      longest_row = std::max(longest_row, static_cast<std::size_t>(t.columns));
      positions_[i].reset(request_.precision, samples_[i].count());
      normals_[i].reset(request_.precision, request_.normals ? samples_[i].count() : 0);
    }
    for (std::size_t k = 0; k < p.tables.size(); ++k) {
      const int n = static_cast<int>(p.tables[k].params.size());
      if (!p.tables[k].parameter_major) p.v_tables.push_back(static_cast<int>(k));
      for (int begin = 0; begin < n; begin += kTableChunk)
        p.table_chunks.push_back({static_cast<int>(k), begin, std::min(n, begin + kTableChunk)});
    }
    p.curve.assign(threads_, AlignedVector<T>(widest));
    if (request_.normals) {
      p.curve_du.assign(threads_, AlignedVector<T>(widest));
      p.unresolved.assign(threads_, AlignedVector<T>(longest_row));
    }
    if (streaming_) {
      p.staged_positions.assign(threads_, AlignedVector<T>(longest_row * 3));
      if (request_.normals) p.staged_normals.assign(threads_, AlignedVector<T>(longest_row * 3));
    }
    return p;
  }

  // The row index of every trimmed surface, its mask's storage and the (surface, u sample) rows
  // classify() spreads over the threads.
  void prepare_trims(const Scene& scene) {
    trims_.clear();
    inside_.resize(scene.surfaces.size());  // kept storage, as positions_
    trim_rows_.clear();
    classified_ = false;
    for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      if (!s.trim) {
        trims_.emplace_back();
        inside_[i].clear();
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
  void evaluate_row(Prepared<T>& p, int surface, int a, int thread) {
    const TensorSurface<T>& t = p.surfaces[surface];
    const AxisTable<T>& tu = p.tables[t.table_u];
    const AxisTable<T>& tv = p.tables[t.table_v];
    const T* net = t.net.homogeneous.data()->data();
    const int order_u = t.net.degree_u + 1;
    const bool normals = request_.normals;
    T* curve = p.curve[thread].data();
    T* curve_du = normals ? p.curve_du[thread].data() : nullptr;
    const int first_row = tu.spans[a] - t.net.degree_u;
    using Contraction = void (*)(const T*, int, int, int, const T*, T*);
    const Contraction contract_rows =
        simd_ ? static_cast<Contraction>(tensor::contract_rows)
              : static_cast<Contraction>(tensor::no_simd::contract_rows);
    contract_rows(net, t.net.count_v, first_row, t.net.degree_u, tu.basis.data() + a * order_u,
                  curve);
    if (normals)
      contract_rows(net, t.net.count_v, first_row, t.net.degree_u, tu.ders.data() + a * order_u,
                    curve_du);
    tensor::RowJob<T> job;
    job.curve = curve;
    job.curve_du = curve_du;
    job.run_begin = tv.run_begin.data();
    job.run_first = tv.run_first.data();
    job.runs = static_cast<int>(tv.run_first.size());
    job.degree_v = t.net.degree_v;
    job.rational = t.rational;
    job.count_v_samples = t.columns;
    job.basis_v = tv.basis.data();
    job.basis_dv = normals ? tv.ders.data() : nullptr;
    const std::size_t offset = static_cast<std::size_t>(a) * t.columns * 3;
    T* positions = positions_[surface].template data<T>() + offset;
    T* normals_out = normals ? normals_[surface].template data<T>() + offset : nullptr;
    job.positions = streaming_ ? p.staged_positions[thread].data() : positions;
    job.normals = streaming_ && normals ? p.staged_normals[thread].data() : normals_out;
    job.unresolved = normals ? p.unresolved[thread].data() : nullptr;
    if (simd_)
      tensor::evaluate_row(job);
    else
      tensor::no_simd::evaluate_row(job);
    // Collapsed edges and other places where Su x Sv is rounding noise: the reference's own
    // limit-normal rule (nurbs_math.h surface_normal), rare, so scalar.
    const bool flagged = normals && any_flagged(job.unresolved, t.columns);
    for (int b = 0; flagged && b < t.columns; ++b) {
      if (job.unresolved[b] == T(0)) continue;
      const Vec3<T> n = surface_normal(t.net, tu.params[a], tv.params[b]);
      for (int c = 0; c < 3; ++c) job.normals[3 * b + c] = n[c];
    }
    if (!streaming_) return;
    const std::size_t values = static_cast<std::size_t>(t.columns) * 3;
    tensor::stream_copy(positions, job.positions, values);
    if (normals) tensor::stream_copy(normals_out, job.normals, values);
  }

  template <typename T>
  void evaluate_all(Prepared<T>& p) {
    const int rows = static_cast<int>(p.rows.size());
    const int chunks = static_cast<int>(p.table_chunks.size());
    const int v_tables = static_cast<int>(p.v_tables.size());
    // One parallel region and three loops over every surface's work, so a scene of many small
    // faces pays two barriers in all, not a team's worth of them per face.
#pragma omp parallel num_threads(threads_)
    {
#pragma omp for schedule(dynamic, 1)
      for (int c = 0; c < chunks; ++c) {
        const TableChunk& chunk = p.table_chunks[c];
        fill_table_chunk(p.tables[chunk.table], chunk.begin, chunk.end, request_.normals);
      }
#pragma omp for schedule(static)
      for (int k = 0; k < v_tables; ++k) find_runs(p.tables[p.v_tables[k]]);
#pragma omp for schedule(static) nowait
      for (int r = 0; r < rows; ++r) {
        evaluate_row(p, p.rows[r].first, p.rows[r].second, omp_get_thread_num());
      }
      if (streaming_) tensor::stream_fence();
    }
  }

  int threads_;
  bool simd_;
  bool streaming_;
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
  return host_entry<CpuTensor>(
      {"cpu-tensor",
       "tensor-product grid evaluation with per-row/column basis tables (004, Macri 1999), "
       "SIMD across samples, OpenMP across rows",
       "baseline", tensor_capabilities()});
}

}  // namespace nurbs
