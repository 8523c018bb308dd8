#include "strategies/trim_direct/trim_tables.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "reference/trim_classify.h"
#include "reference/trim_crossings.h"
#include "strategies/strategy_options.h"

namespace nurbs::trim_direct {

// The C++ compiles of the single-source classifier: float as the GPU stages run it, double as
// OpenCL runs it where the device has fp64. Tests hold them against the reference classifier,
// which keeps its own root isolation on the whole pieces (trim_crossings.h): an independent
// oracle, so a mistake in the monotone split, the rows or the bisection cannot hide in both.
namespace f32 {
#define TD_REAL float
#include "strategies/trim_direct/trim_direct.h"
#undef TD_REAL
}  // namespace f32
namespace f64 {
#define TD_REAL double
#include "strategies/trim_direct/trim_direct.h"
#undef TD_REAL
}  // namespace f64

namespace {

using Homogeneous = std::array<std::array<double, 3>, kMaxOrder>;

// The Bernstein coefficients of the product of two Bernstein polynomials of degrees a and b.
void bernstein_product(const double* p, int a, const double* q, int b, double* out) {
  const auto choose = [](int n, int k) {
    double c = 1;
    for (int i = 1; i <= k; ++i) c = c * (n - k + i) / i;
    return c;
  };
  for (int k = 0; k <= a + b; ++k) out[k] = 0;
  for (int i = 0; i <= a; ++i)
    for (int j = 0; j <= b; ++j)
      out[i + j] += choose(a, i) * choose(b, j) / choose(a + b, i + j) * p[i] * q[j];
}

// Coefficients of x'w - xw' for a piece of degree n <= kMaxDegree: 2n of them.
constexpr int kNumeratorCapacity = 2 * kMaxDegree;

// The parameters in (0, 1) where coordinate c (0: u, 1: v) of the piece has an extremum: roots of
// x'w - xw' (degree 2n - 1 in Bernstein form), by the reference's Bernstein root isolation sized
// for that degree (up to 29 at trim degree 15).
void extrema(const Homogeneous& h, int n, int c, std::vector<double>& roots) {
  double x[kMaxOrder], w[kMaxOrder], dx[kMaxOrder], dw[kMaxOrder];
  double a[kNumeratorCapacity], b[kNumeratorCapacity];
  for (int i = 0; i <= n; ++i) {
    x[i] = h[i][c];
    w[i] = h[i][2];
  }
  for (int i = 0; i < n; ++i) {
    dx[i] = n * (x[i + 1] - x[i]);
    dw[i] = n * (w[i + 1] - w[i]);
  }
  bernstein_product(dx, n - 1, w, n, a);
  bernstein_product(x, n, dw, n - 1, b);
  for (int i = 0; i <= 2 * n - 1; ++i) a[i] -= b[i];
  trim_detail::isolate_roots<double, kNumeratorCapacity>(a, 2 * n - 1, 0.0, 1.0, 0, roots);
}

// de Casteljau split of homogeneous points at t: `left` on [0, t], `h` becomes [t, 1].
void split(Homogeneous& h, int n, double t, Homogeneous& left) {
  for (int r = 0; r <= n; ++r) {
    left[r] = h[0];
    for (int i = 0; i < n - r; ++i)
      for (int c = 0; c < 3; ++c) h[i][c] = (1 - t) * h[i][c] + t * h[i + 1][c];
  }
}

MonotonePiece cartesian(const Homogeneous& h, int n) {
  MonotonePiece p;
  p.degree = n;
  for (int i = 0; i <= n; ++i) p.points.push_back({h[i][0] / h[i][2], h[i][1] / h[i][2], h[i][2]});
  return p;
}

}  // namespace

std::vector<MonotonePiece> monotone_pieces(const Trim& trim, double origin_u, double origin_v) {
  std::vector<MonotonePiece> out;
  std::vector<double> roots, scratch;
  for (const auto& loop : trim_pieces<double>(trim).loops) {
    std::vector<MonotonePiece> pieces;
    for (const TrimPiece<double>& piece : loop) {
      // Validation (reference/trim_validation.cpp) holds trim degrees to kMaxDegree; the
      // device side's arrays hold TD_MAX_ORDER = kMaxOrder points.
      const int n = piece.degree;
      Homogeneous h{};
      for (int i = 0; i <= n; ++i)
        h[i] = {piece.h[i][0] - origin_u * piece.h[i][2], piece.h[i][1] - origin_v * piece.h[i][2],
                piece.h[i][2]};
      roots.clear();
      for (int c = 0; c < 2; ++c) {
        scratch.clear();
        extrema(h, n, c, scratch);
        roots.insert(roots.end(), scratch.begin(), scratch.end());
      }
      std::sort(roots.begin(), roots.end());
      // A split nearer than this to an end or to the previous split would leave a sliver whose
      // only effect is a degenerate row.
      constexpr double kMinSplit = 1e-12;
      double start = 0;
      for (double t : roots) {
        if (t <= start + kMinSplit || t >= 1 - kMinSplit) continue;
        Homogeneous left{};
        split(h, n, (t - start) / (1 - start), left);
        pieces.push_back(cartesian(left, n));
        start = t;
      }
      pieces.push_back(cartesian(h, n));
    }
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      out.push_back(pieces[k]);
      const auto& end = pieces[k].points.back();
      const auto& next = pieces[(k + 1) % pieces.size()].points.front();
      if (end[0] != next[0] || end[1] != next[1])
        out.push_back({1, {{end[0], end[1], 1.0}, {next[0], next[1], 1.0}}});
    }
  }
  return out;
}

Settings settings_from(const StrategyOptions& options, std::string_view strategy) {
  Settings s;
  if (auto it = options.extra.find("trim-epsilon");
      it != options.extra.end() && !it->second.empty()) {
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(it->second, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != it->second.size() || !(value > 0 && value < 1))
      throw std::invalid_argument(
          fmt::format("{} option trim-epsilon = '{}': must be a number in (0, 1) (a fraction of "
                      "the surface's domain diagonal)",
                      strategy, it->second));
    s.epsilon = value;
  }
  if (const int n = positive_option(options, "trim-iterations", strategy); n > 0) {
    if (n > 64)
      throw std::invalid_argument(fmt::format(
          "{} option trim-iterations = '{}': at most 64 (a double halves to nothing by then)",
          strategy, n));
    s.iterations = n;
  }
  return s;
}

template <typename T>
TrimTables<T> build_tables(const Scene& scene, const Settings& settings) {
  TrimTables<T> t;
  for (const Surface& surface : scene.surfaces) {
    typename TrimTables<T>::SurfaceTrim& st = t.surfaces.emplace_back();
    if (!surface.trim) continue;
    double lo[2] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max()};
    double hi[2] = {std::numeric_limits<double>::lowest(), std::numeric_limits<double>::lowest()};
    for (const TrimLoop& loop : surface.trim->loops)
      for (const TrimCurve& curve : loop.curves)
        for (const Point2& p : curve.points)
          for (int c = 0; c < 2; ++c) {
            lo[c] = std::min(lo[c], p[c]);
            hi[c] = std::max(hi[c], p[c]);
          }
    if (lo[0] <= hi[0]) {
      st.origin_u = 0.5 * (lo[0] + hi[0]);
      st.origin_v = 0.5 * (lo[1] + hi[1]);
    }
    st.epsilon = static_cast<T>(settings.epsilon * domain_diagonal(surface));
    st.base = static_cast<int>(t.ints.size());
    // Every piece rounded to T once: its stored ends are the row breaks.
    struct Stored {
      std::size_t real;  // index of u-min in t.reals
      int degree;
      T v_lo, v_hi, u_lo;
    };
    std::vector<Stored> stored;
    std::vector<T> breaks;
    const std::size_t breaks_at = t.reals.size();
    const std::vector<MonotonePiece> pieces =
        monotone_pieces(*surface.trim, st.origin_u, st.origin_v);
    for (const MonotonePiece& p : pieces) {
      const T u0 = static_cast<T>(p.points.front()[0]), v0 = static_cast<T>(p.points.front()[1]);
      const T u1 = static_cast<T>(p.points.back()[0]), v1 = static_cast<T>(p.points.back()[1]);
      breaks.push_back(v0);
      breaks.push_back(v1);
      stored.push_back({0, p.degree, std::min(v0, v1), std::max(v0, v1), std::min(u0, u1)});
    }
    std::sort(breaks.begin(), breaks.end());
    breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
    const int rows = breaks.size() < 2 ? 0 : static_cast<int>(breaks.size()) - 1;
    t.reals.insert(t.reals.end(), breaks.begin(), breaks.end());
    std::size_t k = 0;
    for (const MonotonePiece& p : pieces) {
      stored[k].real = t.reals.size();
      const T u0 = static_cast<T>(p.points.front()[0]), u1 = static_cast<T>(p.points.back()[0]);
      t.reals.push_back(std::min(u0, u1));
      t.reals.push_back(std::max(u0, u1));
      for (const auto& q : p.points)
        for (double x : q) t.reals.push_back(static_cast<T>(x));
      ++k;
    }
    // Row r is (breaks[r], breaks[r + 1]]; a piece spans rows lower_bound(v_lo) .. of v_hi - 1.
    std::vector<std::vector<const Stored*>> row_pieces(static_cast<std::size_t>(rows));
    for (const Stored& s : stored) {
      const auto first = std::lower_bound(breaks.begin(), breaks.end(), s.v_lo) - breaks.begin();
      const auto last = std::lower_bound(breaks.begin(), breaks.end(), s.v_hi) - breaks.begin();
      for (auto r = first; r < last; ++r) row_pieces[static_cast<std::size_t>(r)].push_back(&s);
    }
    t.ints.push_back(rows);
    t.ints.push_back(static_cast<std::int32_t>(breaks_at));
    const std::size_t starts = t.ints.size();
    t.ints.resize(starts + static_cast<std::size_t>(rows) + 1);
    for (int r = 0; r < rows; ++r) {
      auto& list = row_pieces[static_cast<std::size_t>(r)];
      std::stable_sort(list.begin(), list.end(),
                       [](const Stored* a, const Stored* b) { return a->u_lo < b->u_lo; });
      t.ints[starts + static_cast<std::size_t>(r)] = static_cast<std::int32_t>(t.ints.size());
      for (const Stored* s : list) {
        t.ints.push_back(static_cast<std::int32_t>(s->real));
        t.ints.push_back(s->degree);
      }
      t.entries += list.size();
    }
    t.ints[starts + static_cast<std::size_t>(rows)] = static_cast<std::int32_t>(t.ints.size());
    t.pieces += stored.size();
    t.rows += static_cast<std::size_t>(rows);
  }
  if (t.ints.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) ||
      t.reals.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    throw RefusedError("direct trimming: the trim tables exceed 32-bit indices");
  return t;
}

template <typename T>
int classify_packed(const TrimTables<T>& tables, std::size_t surface, T u, T v, int iterations) {
  const auto& s = tables.surfaces[surface];
  if constexpr (sizeof(T) == sizeof(float))
    return f32::td_classify(tables.reals.data(), tables.ints.data(), s.base, u, v, s.epsilon,
                            iterations);
  else
    return f64::td_classify(tables.reals.data(), tables.ints.data(), s.base, u, v, s.epsilon,
                            iterations);
}

template <typename T>
std::vector<std::uint8_t> classify_samples(const TrimTables<T>& tables, std::size_t surface,
                                           const SurfaceSamples& samples, int iterations,
                                           Cost* cost) {
  const auto& s = tables.surfaces[surface];
  std::vector<std::uint8_t> inside(samples.count());
  for (std::size_t k = 0; k < inside.size(); ++k) {
    const int packed = classify_packed(tables, surface, local_u<T>(s, samples.u_of(k)),
                                       local_v<T>(s, samples.v_of(k)), iterations);
    inside[k] = static_cast<std::uint8_t>(packed & 1);
    if (cost) cost->add(packed);
  }
  return inside;
}

void record_settings(const Settings& settings, DeviceInfo& info) {
  info.details["trim_method"] = "direct (Schollmeyer & Froehlich 2009): monotone pieces, bisection";
  info.details["trim_epsilon"] = fmt::format("{:g} x domain diagonal", settings.epsilon);
  info.details["trim_iterations"] = std::to_string(settings.iterations);
}

void record_cost(const Cost& cost, DeviceInfo& info) {
  if (cost.samples == 0) return;
  info.details["trim_reads_per_sample_mean"] =
      fmt::format("{:.2f}", static_cast<double>(cost.reads) / static_cast<double>(cost.samples));
  info.details["trim_reads_per_sample_max"] = std::to_string(cost.max_reads);
}

template TrimTables<float> build_tables<float>(const Scene&, const Settings&);
template TrimTables<double> build_tables<double>(const Scene&, const Settings&);
template int classify_packed<float>(const TrimTables<float>&, std::size_t, float, float, int);
template int classify_packed<double>(const TrimTables<double>&, std::size_t, double, double, int);
template std::vector<std::uint8_t> classify_samples<float>(const TrimTables<float>&, std::size_t,
                                                           const SurfaceSamples&, int, Cost*);
template std::vector<std::uint8_t> classify_samples<double>(const TrimTables<double>&, std::size_t,
                                                            const SurfaceSamples&, int, Cost*);

}  // namespace nurbs::trim_direct
