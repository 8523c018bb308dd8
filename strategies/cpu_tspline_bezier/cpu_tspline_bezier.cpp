#include "strategies/cpu_tspline_bezier/cpu_tspline_bezier.h"

#include <fmt/format.h>
#include <omp.h>

#include <algorithm>
#include <memory>
#include <type_traits>
#include <variant>
#include <vector>

#include "reference/nurbs_math.h"
#include "reference/tspline.h"
#include "reference/tspline_extraction.h"
#include "strategies/aligned_vector.h"
#include "strategies/cpu_tensor/tensor_kernels.h"
#include "strategies/strategy_options.h"

namespace nurbs {
namespace {

Capabilities tspline_bezier_capabilities() {
  Capabilities c;
  c.max_degree = kMaxDegree;
  c.tspline = true;
  c.tspline_only = true;            // its NURBS counterpart is cpu-tensor
  c.updates_control_points = true;  // the nets only: index and operators are topology
  return c;
}

// What prepare() derives from a surface's topology and keeps for update_control_points().
struct Topology {
  std::shared_ptr<const TSplineSurface> tspline;
  TSplineInfluence index;
  TSplineExtraction extraction;
};

// The Bernstein polynomials of `degree` (and their first derivatives when `ders`) at x on the
// element [lo, hi]: A2.2 / A2.3 on the clamped knot vector [0^(p+1), 1^(p+1)] at the local
// parameter, all in long double, rounded once to T.
template <typename T>
void bernstein(int degree, double lo, double hi, double x, T* basis, T* ders) {
  using LD = long double;
  LD knots[2 * kMaxOrder];
  for (int i = 0; i <= degree; ++i) {
    knots[i] = 0;
    knots[degree + 1 + i] = 1;
  }
  const LD width = LD(hi) - LD(lo), t = (LD(x) - LD(lo)) / width;
  LD d[2][kMaxOrder];
  if (ders)
    basis_function_derivatives(degree, t, degree, 1, knots, d);
  else
    basis_functions(degree, t, degree, knots, d[0]);
  for (int k = 0; k <= degree; ++k) {
    basis[k] = T(d[0][k]);
    if (ders) ders[k] = T(d[1][k] / width);
  }
}

// One direction's samples of one surface: their elements and Bernstein tables, filled in
// evaluate() (part of the work from parameters to points, as cpu-tensor's tables are). u tables
// hold one sample's functions together ([a * (p+1) + k]); v tables one function's samples
// together ([l * n + b]), which the row kernel's sample loop reads contiguously.
template <typename T>
struct ElementTable {
  bool parameter_major = false;
  std::vector<int> cells;
  std::vector<T> basis, ders;
  // v tables: runs of consecutive samples in one element column (tensor::RowJob).
  std::vector<int> run_begin, run_first;
};

template <typename T>
struct SurfaceWork {
  int topology = 0;
  // Element (cu, cv)'s homogeneous point (k, l) at row cu (p+1) + k, column cv (q+1) + l, xyzw,
  // about `origin`: (w (P - origin), w). Bézier points of one element lie closer together than the
  // B-spline points they come from, so with absolute coordinates a far-from-origin surface lost
  // the derivatives to cancellation (far-origin f32: 1.2 degrees of normal error against
  // cpu-tspline's 0.23); about the control points' bounding-box centre it keeps them, and the
  // origin comes back as one addition per position.
  std::vector<T> net;
  Vec3<T> origin{};
  int net_columns = 0;
  ElementTable<T> u, v;
};

// A piece of one surface's table (axis 0: u, 1: v) or explicit list: the unit threads share.
struct Chunk {
  int surface = 0, axis = 0, begin = 0, end = 0;
};
inline constexpr int kChunk = 256;

class CpuTSplineBezier final : public Strategy {
 public:
  explicit CpuTSplineBezier(const StrategyOptions& options) : threads_(openmp_threads(options)) {}

  std::string_view name() const override { return "cpu-tspline-bezier"; }
  Capabilities capabilities() const override { return tspline_bezier_capabilities(); }
  DeviceInfo device() const override {
    return {fmt::format("host CPU, {} thread{} (OpenMP)", threads_, threads_ == 1 ? "" : "s"),
            "cpu",
            {{"threads", std::to_string(threads_)}, {"elements", std::to_string(elements_)}}};
  }

  void prepare_checked(const Scene& scene, const EvalRequest& request) override {
    request_ = request;
    samples_ = sample_parameters(scene, request.sampling);
    topology_.clear();
    elements_ = 0;
    for (const Surface& s : scene.surfaces) {
      TSplineInfluence index(*s.tspline, s.name);
      TSplineExtraction extraction = extract_bezier_elements(*s.tspline, index);
      elements_ += extraction.elements.size();
      topology_.push_back(
          std::make_unique<Topology>(Topology{s.tspline, std::move(index), std::move(extraction)}));
    }
    if (request.precision == Precision::f32)
      prepared_ = prepare_all<float>();
    else
      prepared_ = prepare_all<double>();
  }

  void update_control_points(const Scene& scene) override {
    for (std::size_t i = 0; i < topology_.size(); ++i) {
      const Surface& s = scene.surfaces[i];
      if (!s.is_tspline() || !same_extraction_topology(*s.tspline, *topology_[i]->tspline)) {
        prepare(scene, request_);
        return;
      }
      topology_[i]->tspline = s.tspline;
    }
    std::visit(
        [this](auto& p) {
          for (auto& w : p.surfaces) fill_net(w);
        },
        prepared_);
  }

  void evaluate() override {
    std::visit([this](auto& p) { evaluate_all(p); }, prepared_);
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
      copy_surface_into(out.surfaces[i], samples_[i], positions_[i], normals_[i]);
  }

 private:
  template <typename T>
  struct Prepared {
    std::vector<SurfaceWork<T>> surfaces;
    std::vector<Chunk> chunks;              // tables, or explicit samples
    std::vector<std::pair<int, int>> rows;  // (surface, u sample) of the tensor samplings
    // Per thread, each on cache lines of its own (AlignedVector: no false sharing between threads).
    std::vector<AlignedVector<T>> curve, curve_du, unresolved;
  };

  template <typename T>
  void fill_net(SurfaceWork<T>& w) const {
    const Topology& t = *topology_[w.topology];
    const int p = t.extraction.degree_u, q = t.extraction.degree_v;
    std::vector<Vec4<long double>> points(static_cast<std::size_t>(p + 1) * (q + 1));
    Point3 lo = t.tspline->points.front(), hi = lo;
    for (const Point3& point : t.tspline->points)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], point[c]);
        hi[c] = std::max(hi[c], point[c]);
      }
    // Rounded to T first: the net is formed about exactly the origin added back.
    for (int c = 0; c < 3; ++c) w.origin[c] = T(lo[c] / 2 + hi[c] / 2);
    for (const BezierElement& e : t.extraction.elements) {
      element_homogeneous_points(*t.tspline, t.extraction, e, points.data());
      for (int k = 0; k <= p; ++k)
        for (int l = 0; l <= q; ++l) {
          const std::size_t at = (static_cast<std::size_t>(e.cell_u * (p + 1) + k) * w.net_columns +
                                  e.cell_v * (q + 1) + l) *
                                 4;
          const Vec4<long double>& h = points[k * (q + 1) + l];
          for (int c = 0; c < 3; ++c)
            w.net[at + c] = T(h[c] - static_cast<long double>(w.origin[c]) * h[3]);
          w.net[at + 3] = T(h[3]);
        }
    }
  }

  template <typename T>
  Prepared<T> prepare_all() {
    Prepared<T> p;
    std::size_t widest = 0, longest_row = 0;
    // Resized, not reassigned: a prepare() of the same request keeps the output buffers.
    positions_.resize(topology_.size());
    normals_.resize(topology_.size());
    for (std::size_t i = 0; i < topology_.size(); ++i) {
      const Topology& t = *topology_[i];
      const SurfaceSamples& samples = samples_[i];
      const int surface = static_cast<int>(i);
      SurfaceWork<T>& w = p.surfaces.emplace_back();
      w.topology = surface;
      const int p_u = t.extraction.degree_u, q_v = t.extraction.degree_v;
      w.net_columns = t.index.cells_v() * (q_v + 1);
      w.net.resize(static_cast<std::size_t>(t.index.cells_u()) * (p_u + 1) * w.net_columns * 4);
      fill_net(w);
      positions_[i].reset(request_.precision, samples.count());
      normals_[i].reset(request_.precision, request_.normals ? samples.count() : 0);
      const int nu = static_cast<int>(samples.u.size()), nv = static_cast<int>(samples.v.size());
      if (!samples.tensor) {
        for (int b = 0; b < nu; b += kChunk)
          p.chunks.push_back({surface, 0, b, std::min(nu, b + kChunk)});
        continue;
      }
      resize_table(w.u, nu, p_u, true);
      resize_table(w.v, nv, q_v, false);
      for (int b = 0; b < nu; b += kChunk)
        p.chunks.push_back({surface, 0, b, std::min(nu, b + kChunk)});
      for (int b = 0; b < nv; b += kChunk)
        p.chunks.push_back({surface, 1, b, std::min(nv, b + kChunk)});
      for (int a = 0; a < nu; ++a) p.rows.emplace_back(surface, a);
      widest = std::max(widest, static_cast<std::size_t>(w.net_columns) * 4);
      longest_row = std::max(longest_row, static_cast<std::size_t>(nv));
    }
    p.curve.assign(threads_, AlignedVector<T>(widest));
    if (request_.normals) {
      p.curve_du.assign(threads_, AlignedVector<T>(widest));
      p.unresolved.assign(threads_, AlignedVector<T>(longest_row));
    }
    return p;
  }

  template <typename T>
  void resize_table(ElementTable<T>& t, int n, int degree, bool parameter_major) const {
    const std::size_t values = static_cast<std::size_t>(n) * (degree + 1);
    t.parameter_major = parameter_major;
    t.cells.resize(n);
    t.basis.resize(values);
    t.ders.resize(request_.normals ? values : 0);
    t.run_begin.reserve(n + 1);
    t.run_first.reserve(n);
  }

  // Elements and Bernstein functions of the parameters [begin, end) of one table.
  template <typename T>
  void fill_chunk(Prepared<T>& p, const Chunk& chunk) const {
    SurfaceWork<T>& w = p.surfaces[chunk.surface];
    const Topology& t = *topology_[w.topology];
    const bool u_axis = chunk.axis == 0;
    ElementTable<T>& table = u_axis ? w.u : w.v;
    const std::vector<double>& params =
        u_axis ? samples_[chunk.surface].u : samples_[chunk.surface].v;
    const std::vector<double>& breaks = u_axis ? t.index.breaks_u() : t.index.breaks_v();
    const int degree = u_axis ? t.extraction.degree_u : t.extraction.degree_v;
    const std::size_t n = params.size(), order = static_cast<std::size_t>(degree) + 1;
    for (int a = chunk.begin; a < chunk.end; ++a) {
      const int cell = u_axis ? t.index.cell_u(params[a]) : t.index.cell_v(params[a]);
      table.cells[a] = cell;
      T basis[kMaxOrder], ders[kMaxOrder];
      bernstein<T>(degree, breaks[cell], breaks[cell + 1], params[a], basis,
                   request_.normals ? ders : nullptr);
      for (std::size_t k = 0; k < order; ++k) {
        const std::size_t at = table.parameter_major ? a * order + k : k * n + a;
        table.basis[at] = basis[k];
        if (request_.normals) table.ders[at] = ders[k];
      }
    }
  }

  template <typename T>
  static void find_runs(ElementTable<T>& t, int degree) {
    t.run_begin.clear();
    t.run_first.clear();
    const int n = static_cast<int>(t.cells.size());
    for (int b = 0; b < n; ++b)
      if (b == 0 || t.cells[b] != t.cells[b - 1]) {
        t.run_begin.push_back(b);
        t.run_first.push_back(t.cells[b] * (degree + 1));
      }
    t.run_begin.push_back(n);
  }

  // One grid row: the u contraction of the sample's element row into the iso-curve's Bézier
  // points (every element column), then cpu-tensor's v kernel.
  template <typename T>
  void evaluate_row(Prepared<T>& p, int surface, int a, int thread) {
    const SurfaceWork<T>& w = p.surfaces[surface];
    const Topology& t = *topology_[w.topology];
    const int deg_u = t.extraction.degree_u, order_u = deg_u + 1;
    const bool normals = request_.normals;
    const int columns = static_cast<int>(samples_[surface].v.size());
    T* curve = p.curve[thread].data();
    T* curve_du = normals ? p.curve_du[thread].data() : nullptr;
    const int first_row = w.u.cells[a] * order_u;
    tensor::contract_rows(w.net.data(), w.net_columns, first_row, deg_u,
                          w.u.basis.data() + a * order_u, curve);
    if (normals)
      tensor::contract_rows(w.net.data(), w.net_columns, first_row, deg_u,
                            w.u.ders.data() + a * order_u, curve_du);
    tensor::RowJob<T> job;
    job.curve = curve;
    job.curve_du = curve_du;
    job.run_begin = w.v.run_begin.data();
    job.run_first = w.v.run_first.data();
    job.runs = static_cast<int>(w.v.run_first.size());
    job.degree_v = t.extraction.degree_v;
    job.rational = true;  // a T-spline always divides by its blending sum
    job.count_v_samples = columns;
    job.basis_v = w.v.basis.data();
    job.basis_dv = normals ? w.v.ders.data() : nullptr;
    const std::size_t offset = static_cast<std::size_t>(a) * columns * 3;
    job.positions = positions_[surface].template data<T>() + offset;
    job.normals = normals ? normals_[surface].template data<T>() + offset : nullptr;
    job.unresolved = normals ? p.unresolved[thread].data() : nullptr;
    tensor::evaluate_row(job);
    for (int b = 0; b < columns; ++b)
      for (int c = 0; c < 3; ++c) job.positions[3 * b + c] += w.origin[c];
    // The T-spline reference has no limit normal: an unresolved one is zero there.
    for (int b = 0; normals && b < columns; ++b)
      if (job.unresolved[b] != T(0)) std::fill_n(job.normals + 3 * b, 3, T(0));
  }

  // One sample of an explicit list: its element, both Bernstein bases and the (p+1)(q+1) sum;
  // the rational quotient and normal as the reference forms them (reference/tspline.h).
  template <typename T>
  void evaluate_sample(const SurfaceWork<T>& w, int surface, std::size_t k) {
    const Topology& t = *topology_[w.topology];
    const int p = t.extraction.degree_u, q = t.extraction.degree_v;
    const double u = samples_[surface].u_of(k), v = samples_[surface].v_of(k);
    const int cu = t.index.cell_u(u), cv = t.index.cell_v(v);
    const bool normals = request_.normals;
    T bu[kMaxOrder], du[kMaxOrder], bv[kMaxOrder], dv[kMaxOrder];
    bernstein<T>(p, t.index.breaks_u()[cu], t.index.breaks_u()[cu + 1], u, bu,
                 normals ? du : nullptr);
    bernstein<T>(q, t.index.breaks_v()[cv], t.index.breaks_v()[cv + 1], v, bv,
                 normals ? dv : nullptr);
    Vec4<T> sum{}, sum_u{}, sum_v{};
    for (int a = 0; a <= p; ++a) {
      const T* row =
          w.net.data() +
          (static_cast<std::size_t>(cu * (p + 1) + a) * w.net_columns + cv * (q + 1)) * 4;
      for (int b = 0; b <= q; ++b)
        for (int c = 0; c < 4; ++c) {
          sum[c] += bu[a] * bv[b] * row[4 * b + c];
          if (normals) {
            sum_u[c] += du[a] * bv[b] * row[4 * b + c];
            sum_v[c] += bu[a] * dv[b] * row[4 * b + c];
          }
        }
    }
    Vec3<T> point, su, sv, normal{};
    for (int c = 0; c < 3; ++c) point[c] = sum[c] / sum[3];
    Vec3<T> moved = point;
    for (int c = 0; c < 3; ++c) moved[c] += w.origin[c];
    positions_[surface].set(k, moved);
    if (!normals) return;
    for (int c = 0; c < 3; ++c) {
      su[c] = (sum_u[c] - sum_u[3] * point[c]) / sum[3];
      sv[c] = (sum_v[c] - sum_v[3] * point[c]) / sum[3];
    }
    detail::normalize_if_resolved(cross(su, sv), su, sv, normal);
    normals_[surface].set(k, normal);
  }

  template <typename T>
  void evaluate_all(Prepared<T>& p) {
    const int chunks = static_cast<int>(p.chunks.size());
    const int surfaces = static_cast<int>(p.surfaces.size());
    const int rows = static_cast<int>(p.rows.size());
    const bool tensor = request_.sampling.mode != SamplingMode::explicit_list;
#pragma omp parallel num_threads(threads_)
    {
      if (!tensor) {
#pragma omp for schedule(dynamic, 1)
        for (int c = 0; c < chunks; ++c) {
          const Chunk& chunk = p.chunks[c];
          for (int k = chunk.begin; k < chunk.end; ++k)
            evaluate_sample(p.surfaces[chunk.surface], chunk.surface, k);
        }
      } else {
#pragma omp for schedule(dynamic, 1)
        for (int c = 0; c < chunks; ++c) fill_chunk(p, p.chunks[c]);
#pragma omp for schedule(static)
        for (int s = 0; s < surfaces; ++s)
          find_runs(p.surfaces[s].v, topology_[p.surfaces[s].topology]->extraction.degree_v);
#pragma omp for schedule(static)
        for (int r = 0; r < rows; ++r)
          evaluate_row(p, p.rows[r].first, p.rows[r].second, omp_get_thread_num());
      }
    }
  }

  int threads_;
  EvalRequest request_;
  std::vector<SurfaceSamples> samples_;
  std::vector<std::unique_ptr<Topology>> topology_;
  std::size_t elements_ = 0;
  std::variant<Prepared<float>, Prepared<double>> prepared_;
  std::vector<PointArray> positions_, normals_;
};

}  // namespace

StrategyEntry cpu_tspline_bezier_entry() {
  return host_entry<CpuTSplineBezier>(
      {"cpu-tspline-bezier",
       "Bézier extraction of the T-spline (Scott et al. 2011) evaluated with cpu-tensor's "
       "kernels: Bernstein tables per row/column, SIMD across samples, OpenMP across rows",
       "strategy", tspline_bezier_capabilities()});
}

}  // namespace nurbs
